#!/usr/bin/env bash
# What a frame costs on the camera boards: cycles per pixel of the hot loops the cross compilers
# emit (llvm-mca with the Cortex-A53, A72 and, standing in for the A7, A9 scheduling models),
# instructions executed per pixel and per VO frame under qemu-user, and from them the pipeline's
# share of one core at 640x512 / 60 Hz and the VO's real-time factor (docs/benchmarks.md).
#   scripts/board-cost.sh [--json] [--method plugin|log] [--targets aarch64,armhf]
# Tables on stdout (or JSON with --json); the JSON also in build/board-cost/board-cost.json, the
# loops and llvm-mca's reports in build/board-cost/loops/.
# Builds what it needs: build-aarch64 / build-armhf (bolo-board-count) and the host build's
# bolo-vo-bench (renders the VO's 320x256 frames).
set -euo pipefail
cd "$(dirname "$0")/.."
targets=aarch64,armhf
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --json) args+=(--json) ;;
    --method) args+=(--method "$2"); shift ;;
    --targets) targets=$2; shift ;;
    *) echo "usage: scripts/board-cost.sh [--json] [--method plugin|log] [--targets aarch64,armhf]" >&2; exit 2 ;;
  esac
  shift
done
jobs=$(nproc)
log=$(mktemp)
trap 'rm -f "$log"' EXIT
build() {  # dir, [cmake args...] -> configures if needed, builds the targets in $targets_to_build
  local dir=$1; shift
  [ -f "$dir/build.ninja" ] || cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
  cmake --build "$dir" -j "$jobs" --target "${targets_to_build[@]}" >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
}
targets_to_build=(bolo-vo-bench)
build build
for target in ${targets//,/ }; do
  case $target in
    aarch64) toolchain=toolchain/aarch64-linux-gnu.cmake ;;
    armhf) toolchain=toolchain/arm-linux-gnueabihf.cmake ;;
    *) echo "board-cost: unknown target '$target' (aarch64, armhf)" >&2; exit 2 ;;
  esac
  targets_to_build=(bolo-board-count)
  build "build-$target" -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DBOLO_BUILD_HOST_TOOLS=OFF
done
frames=build/board-cost/vo-320x256.frames
mkdir -p build/board-cost
# 40 frames of bolo-vo-bench's street drive; the VO's frames 20..39 are counted (past its start)
build/bench/bolo-vo-bench --write-frames "$frames" --sizes 320x256 --frames 40
python3 scripts/board-cost/board_cost.py --targets "$targets" --vo-frames "$frames" --vo-range 20,40 \
  --keep build/board-cost/loops --save-json build/board-cost/board-cost.json "${args[@]}"
