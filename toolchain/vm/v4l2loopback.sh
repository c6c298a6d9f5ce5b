#!/usr/bin/env bash
# Builds v4l2loopback.ko for the HIL VM's kernel out of tree (Debian's kernel does not ship it),
# cached in $BOLO_HIL_CACHE/<arch>/v4l2loopback/v4l2loopback.ko, which hil-vm.sh then packs and
# loads (one device, /dev/video42: `bolo run --sink v4l2:` writes it, a V4L2 capture reads it).
# Sources: Debian's v4l2loopback-dkms package (apt-get download, nothing installed), built
# against the matching linux-headers/kbuild packages unpacked into the cache as for gpio-sim.
#
# For aarch64 the module is cross-built (kernel-cache.sh: hil_module_make_args).
#
#   v4l2loopback.sh [x86_64|aarch64]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
arch="${1:-x86_64}"
# shellcheck source=kernel-cache.sh
source "$here/kernel-cache.sh"
hil_module_start "$arch" v4l2loopback
hil_module_cached v4l2loopback.ko kver && exit 0

hil_module_kbuild
hil_fetch_deb v4l2loopback-dkms "$module_root/dkms" "$cache" >&2
src="$(ls -d "$module_root"/dkms/usr/src/v4l2loopback-*/ | head -1)"
[ -f "$src/v4l2loopback.c" ] || { echo "v4l2loopback: no v4l2loopback.c in the v4l2loopback-dkms package" >&2; exit 1; }
cp "$src"/*.c "$src"/*.h "$out/"
printf 'obj-m := v4l2loopback.o\n' >"$out/Kbuild"
make -s -C "$headers" M="$out" "${HIL_MAKE_ARGS[@]}" modules >&2
echo "$kver" >"$out/kver"
rm -rf "$module_root"
echo "$out/v4l2loopback.ko"
