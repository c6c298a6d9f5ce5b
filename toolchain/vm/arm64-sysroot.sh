#!/usr/bin/env bash
# Unpacks the arm64 runtime and development packages the HIL programs link against (libusb,
# libudev, libgpiod) into a sysroot folder, with `apt-get download` + `dpkg-deb -x`: installing
# them as :arm64 packages trips apt's version-skew check between the amd64 and arm64 indexes.
# Needs `dpkg --add-architecture arm64` and an apt-get update (scripts/deps.sh does both).
# Prints the sysroot's path.
set -euo pipefail
cache="${BOLO_HIL_CACHE:-$HOME/.cache/bolo-hil}"
sysroot="$cache/aarch64/sysroot"
packages=(libusb-1.0-0 libusb-1.0-0-dev libudev1 libgpiod2 libgpiod-dev)
if [ ! -f "$sysroot/.complete" ]; then
  mkdir -p "$cache/deb-arm64" "$sysroot"
  for p in "${packages[@]}"; do
    ls "$cache/deb-arm64/${p}_"*.deb >/dev/null 2>&1 ||
      (cd "$cache/deb-arm64" && apt-get download -qq "$p:arm64" 2>&1 | grep -v unsandboxed >&2 || true)
    deb="$(ls "$cache/deb-arm64/${p}_"*.deb 2>/dev/null | head -1)"
    [ -n "$deb" ] || { echo "arm64-sysroot: apt-get download $p:arm64 failed" >&2; exit 1; }
    dpkg-deb -x "$deb" "$sysroot"
  done
  # The -dev packages' .so links point at /lib paths inside the sysroot; make them relative.
  find "$sysroot" -type l | while read -r link; do
    target="$(readlink "$link")"
    case "$target" in /*) ln -sf "$sysroot$target" "$link" ;; esac
  done
  touch "$sysroot/.complete"
fi
echo "$sysroot"
