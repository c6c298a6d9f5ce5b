#!/usr/bin/env bash
# Installs the Debian 12 packages bolo builds with; does nothing when they are all present.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  catch2 nlohmann-json3-dev libcli11-dev libeigen3-dev libpng-dev
  libusb-1.0-0-dev libgpiod-dev libbenchmark-dev
  g++-aarch64-linux-gnu g++-arm-linux-gnueabihf qemu-user
  clang libclang-rt-14-dev llvm clang-tidy cppcheck
  qemu-system-x86 qemu-system-arm busybox-static kmod cpio patch  # HIL VMs (docs/hil.md; patch: uvc-gadget.sh)
  python3-numpy  # scripts/study/independent_generator.py (the diagnosis study's second generator)
)

# The arm64 HIL VM's kernel and libraries are fetched as arm64 packages (apt-get download).
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo dpkg --add-architecture arm64
  $sudo apt-get update -qq
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "bolo: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
