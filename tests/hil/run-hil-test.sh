#!/usr/bin/env bash
# ctest's entry to a HIL scenario: checks what the VM needs, then boots it (toolchain/vm/hil-vm.sh).
# With BOLO_HIL_DEVICE set (usb:flirone, usb:seek, v4l2:/dev/videoN) the scenario's host-side test
# runs here against that real camera instead (the GPIO scenario: that camera with the lines named
# in BOLO_HIL_GPIO); without it and without qemu, the test is skipped with the reason. Exit 77 = skipped.
#
#   run-hil-test.sh --arch A --scenario S --shared-data DIR [--sysroot DIR] --file F...
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
arch="" scenario="" shared="" sysroot=""
files=()
while [ $# -gt 0 ]; do
  case "$1" in
    --arch) arch="$2"; shift 2 ;;
    --scenario) scenario="$2"; shift 2 ;;
    --shared-data) shared="$2"; shift 2 ;;
    --sysroot) sysroot="$2"; shift 2 ;;
    --file) files+=("$2"); shift 2 ;;
    *) echo "run-hil-test: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
skip() { echo "SKIP: $*"; exit 77; }

# Only the scenarios that replay the real FLIR ONE capture need ../shared; the others run without.
capture="$shared/usb/flirone-pro"
if [ ! -d "$capture" ]; then
  grep -q "flirone-pro" "$scenario" && skip "no FLIR ONE capture at $capture (../shared/data is absent)"
  capture=""
fi

if [ -n "${BOLO_HIL_DEVICE:-}" ]; then
  # A real camera on this machine: the host-side program of the scenario's device, no VM.
  scenario_device="$(sed -n 's/^# device: //p' "$scenario")"
  if [ "$scenario_device" = gpio ]; then  # any camera, with its lines named in BOLO_HIL_GPIO
    [ -n "${BOLO_HIL_GPIO:-}" ] || skip "BOLO_HIL_GPIO is not set (CHIP:sync=N,shutter=N,imminent=N: the camera's lines)"
  else
    case "$BOLO_HIL_DEVICE" in
      "$scenario_device" | "$scenario_device":*) ;;  # v4l2 matches v4l2:/dev/videoN
      *) skip "BOLO_HIL_DEVICE=$BOLO_HIL_DEVICE; this scenario needs $scenario_device" ;;
    esac
  fi
  real_command="$(sed -n 's/^# real: //p' "$scenario")"
  for f in "${files[@]}"; do PATH="$(dirname "$f"):$PATH"; done
  export PATH
  echo "run-hil-test: real device $BOLO_HIL_DEVICE: $real_command"
  eval "$real_command"
  exit $?
fi

vm_arch="$(sed -n 's/^# vm-arch: //p' "$scenario")"
[ -z "$vm_arch" ] || [ "$vm_arch" = "$arch" ] ||
  skip "this scenario's VM run is $vm_arch only (docs/hil.md); on a board, BOLO_HIL_DEVICE runs it on a real camera"
qemu=qemu-system-x86_64
[ "$arch" = aarch64 ] && qemu=qemu-system-aarch64
command -v "$qemu" >/dev/null || skip "$qemu is not installed (scripts/deps.sh installs it)"
command -v busybox >/dev/null || [ "$arch" != x86_64 ] || skip "busybox-static is not installed"
if [ "$arch" = aarch64 ] && [ -z "$sysroot" ]; then
  skip "no BOLO_HIL_SYSROOT with the arm64 runtime libraries (toolchain/vm/arm64-sysroot.sh)"
fi

# Frames per clean run: 1000, CI's length, in either VM (BOLO_HIL_FRAMES=10000 and its SEEK/UVC
# siblings give the endurance run of docs/hil.md). docs/hil.md has the times.
clean_frames=1000
export BOLO_HIL_FRAMES="${BOLO_HIL_FRAMES:-$clean_frames}"
export BOLO_HIL_SEEK_FRAMES="${BOLO_HIL_SEEK_FRAMES:-$clean_frames}"
export BOLO_HIL_UVC_FRAMES="${BOLO_HIL_UVC_FRAMES:-$clean_frames}"
# gpio-sim for the VM's kernel (cross-built for aarch64), built once and cached; without it GPIO
# scenarios skip.
if grep -q "gpio-sim" "$scenario"; then
  "$repo/toolchain/vm/gpio-sim.sh" "$arch" >/dev/null ||
    echo "run-hil-test: gpio-sim build for $arch failed; GPIO steps will skip" >&2
fi
# usb_f_uvc with bulk streaming, built once and cached (cross-built for aarch64); without it
# the UVC scenario skips (Debian's module streams isochronous only).
if grep -q "usb_f_uvc bulk build" "$scenario"; then
  "$repo/toolchain/vm/uvc-gadget.sh" "$arch" >/dev/null || echo "run-hil-test: uvc-gadget build failed; the UVC scenario will skip" >&2
fi
# raw_gadget for the FLIR ONE emulator, built once and cached (cross-built for aarch64); without
# it the FLIR ONE scenario skips.
if grep -q "raw_gadget" "$scenario"; then
  "$repo/toolchain/vm/raw-gadget.sh" "$arch" >/dev/null || echo "run-hil-test: raw-gadget build failed; the FLIR ONE scenario will skip" >&2
fi
# v4l2loopback for `bolo run --sink v4l2:` (uvc.sh), built once and cached; without it that step
# skips. x86-64 only: the arm64 VM checks what differs by architecture, and the loopback's V4L2
# path is the one uvcvideo's step there already takes (its cross build is untried).
if [ "$arch" = x86_64 ] && grep -q "v4l2loopback" "$scenario"; then
  "$repo/toolchain/vm/v4l2loopback.sh" "$arch" >/dev/null || echo "run-hil-test: v4l2loopback build failed; the bolo run step will skip" >&2
fi
args=(--arch "$arch" --scenario "$scenario")
[ -n "$capture" ] && args+=(--file "$capture")
# The recording made from the same capture, for `bolo capture` to reproduce in the VM.
recording="$shared/real/flirone-lepton-telemetry"
[ -d "$recording" ] && args+=(--file "$recording")
# A Lepton 3 recording for the PureThermal emulator to stream (uvc.sh; simulated frames without).
grep -q "lepton3-possum" "$scenario" && [ -d "$shared/real/lepton3-possum" ] && args+=(--file "$shared/real/lepton3-possum")
[ -n "$sysroot" ] && args+=(--sysroot "$sysroot")
for f in "${files[@]}"; do args+=(--file "$f"); done
exec "$repo/toolchain/vm/hil-vm.sh" "${args[@]}"
