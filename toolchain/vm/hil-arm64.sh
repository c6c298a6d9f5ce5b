#!/usr/bin/env bash
# The HIL suite in an arm64 VM: cross-builds the emulators and host-side tests for aarch64
# against the arm64 sysroot (arm64-sysroot.sh), then runs ctest's `hil-arm64` tests, which boot
# Debian's arm64 kernel under qemu-system-aarch64 -M virt -cpu cortex-a53 (TCG).
set -euo pipefail
cd "$(dirname "$0")/../.."
sysroot="$(toolchain/vm/arm64-sysroot.sh)"
dir=build-hil-arm64
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_TOOLCHAIN_FILE=toolchain/vm/aarch64-hil.cmake \
  -DBOLO_HIL_SYSROOT="$sysroot" -DBOLO_BUILD_HOST_TOOLS=OFF -DCMAKE_UNITY_BUILD=ON >/dev/null
targets=(flirone_emulator hil_flirone)
# Listed once: `ninja ... | grep -q` under pipefail fails at random (grep's early exit kills
# ninja with SIGPIPE), which once dropped hil_flirone_hal from a CI build.
available=$(ninja -C "$dir" -t targets all)
# The HAL's FLIR ONE source (where libusb was found), the UVC emulator and its V4L2 and Lepton
# extension-unit host sides; the Seek and GPIO scenarios have their VM run on x86-64 only and
# skip here (tests/hil/CMakeLists.txt).
for optional in hil_flirone_hal uvc_emulator hil_uvc_hal hil_uvc_xu; do
  grep -q "^$optional:" <<<"$available" && targets+=("$optional")
done
cmake --build "$dir" -j "$(nproc)" --target "${targets[@]}"
ctest --test-dir "$dir" -L hil-arm64 --output-on-failure "$@"
