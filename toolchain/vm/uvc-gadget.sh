#!/usr/bin/env bash
# Builds usb_f_uvc.ko (the configfs UVC gadget function, "uvc") for the HIL VM's kernel out of
# tree, with bulk streaming instead of isochronous: dummy_hcd carries no isochronous transfers,
# and Debian's module declares its streaming endpoint isochronous only; and with a PureThermal's
# Lepton extension units in its VideoControl interface (6.1's configfs has no XU support). Cached in
# $BOLO_HIL_CACHE/<arch>/uvc-gadget/usb_f_uvc.ko; hil-vm.sh packs it in place of Debian's.
# Sources: drivers/usb/gadget/function/{f_uvc,uvc_*}.[ch], u_uvc.h from Debian's linux-source-6.1,
# changed by uvc-gadget-bulk.patch (one alternate setting with a bulk IN endpoint, 512-byte
# packets at high speed, one USB request per payload of `bulk_payload` bytes), then by
# uvc-gadget-purethermal-xu.patch (static extension units 3-7 with the PureThermal GUIDs fed by the
# processing unit, the output terminal moved to ID 8; their requests reach the emulator as
# UVC_EVENT_SETUP like the probe/commit ones), built against the
# matching linux-headers/kbuild packages unpacked into the cache (apt-get download, nothing
# installed). The patches must apply exactly: upstream changes fail the build loudly.
#
# For aarch64 the module is cross-built (kernel-cache.sh: hil_module_make_args).
#
#   uvc-gadget.sh [x86_64|aarch64]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
arch="${1:-x86_64}"
patches=("$here/uvc-gadget-bulk.patch" "$here/uvc-gadget-purethermal-xu.patch")
# shellcheck source=kernel-cache.sh
source "$here/kernel-cache.sh"
hil_module_start "$arch" uvc-gadget "$(cat "${patches[@]}" | sha256sum | cut -c1-16)"
hil_module_cached usb_f_uvc.ko stamp && exit 0
hil_module_kbuild

src="$(hil_kernel_sources "$cache" "$series")/drivers/usb/gadget/function"
files=(f_uvc.c f_uvc.h u_uvc.h uvc.h uvc_configfs.c uvc_configfs.h uvc_queue.c uvc_queue.h
       uvc_v4l2.c uvc_v4l2.h uvc_video.c uvc_video.h)
cp "${files[@]/#/$src/}" "$out/"
# Nothing outside these files is included by relative path (checked here, not assumed).
if grep -h '^#include "' "$out"/*.[ch] | grep -v -E '"(f_uvc|u_uvc|uvc|uvc_configfs|uvc_queue|uvc_v4l2|uvc_video)\.h"'; then
  echo "uvc-gadget: the sources include a local header that is not extracted (above)" >&2
  exit 1
fi
for patch_file in "${patches[@]}"; do
  (cd "$out" && patch -p1 --forward --fuzz=0 --no-backup-if-mismatch -r - <"$patch_file" >&2) ||
    { echo "uvc-gadget: $patch_file does not apply to $kver's sources (upstream changed): check it by hand" >&2; exit 1; }
done
printf 'obj-m := usb_f_uvc.o\nusb_f_uvc-y := f_uvc.o uvc_queue.o uvc_v4l2.o uvc_video.o uvc_configfs.o\n' >"$out/Kbuild"
make -s -C "$headers" M="$out" "${HIL_MAKE_ARGS[@]}" modules >&2
modinfo -F parm "$out/usb_f_uvc.ko" | grep -q '^bulk_payload:' ||
  { echo "uvc-gadget: the built module has no bulk_payload parameter" >&2; exit 1; }
echo "$stamp" >"$out/stamp"
rm -rf "$module_root"
echo "$out/usb_f_uvc.ko"
