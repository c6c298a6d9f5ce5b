#!/usr/bin/env bash
# Builds raw_gadget.ko (the USB Raw Gadget interface, /dev/raw-gadget) for the HIL VM's kernel
# out of tree: Debian's kernel has CONFIG_USB_RAW_GADGET off. The FLIR ONE emulator uses it to
# answer every control request itself (SET_CONFIGURATION, SET_INTERFACE with any alternate
# setting), which FunctionFS cannot. Cached in $BOLO_HIL_CACHE/<arch>/raw-gadget/raw_gadget.ko,
# which hil-vm.sh then packs and loads after udc-core and dummy_hcd.
# Source: drivers/usb/gadget/legacy/raw_gadget.c from Debian's linux-source-6.1 (one file, no
# local headers), built against the matching linux-headers/kbuild packages unpacked into the
# cache (apt-get download, nothing installed).
#
# For aarch64 the module is cross-built (kernel-cache.sh: hil_module_make_args).
#
#   raw-gadget.sh [x86_64|aarch64]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
arch="${1:-x86_64}"
# shellcheck source=kernel-cache.sh
source "$here/kernel-cache.sh"
hil_module_start "$arch" raw-gadget
hil_module_cached raw_gadget.ko kver && exit 0

hil_module_kbuild

cp "$(hil_kernel_sources "$cache" "$series")/drivers/usb/gadget/legacy/raw_gadget.c" "$out/"
if grep -h '^#include "' "$out/raw_gadget.c"; then
  echo "raw-gadget: raw_gadget.c includes a local header that is not extracted (above)" >&2
  exit 1
fi
printf 'obj-m := raw_gadget.o\n' >"$out/Kbuild"
make -s -C "$headers" M="$out" "${HIL_MAKE_ARGS[@]}" modules >&2
echo "$kver" >"$out/kver"
rm -rf "$module_root"
echo "$out/raw_gadget.ko"
