#!/usr/bin/env bash
# Builds what runs on a camera board (fixed_point, the core, firmware, hal with its recording I/O,
# their tests) for aarch64 and armhf with Debian's cross compilers, runs the tests under qemu-user,
# and checks that the golden hashes printed on each target are identical to the host's.
# aarch64 builds and tests all of it; armhf (the 32-bit board) the arithmetic: fixed_point, the
# firmware kernels and the board VO, and the golden hashes, which cover the whole corrector.
#   scripts/cross-test.sh [aarch64] [armhf]      (default: both)
set -euo pipefail
cd "$(dirname "$0")/.."
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(aarch64 armhf)
jobs=$(nproc)

golden_hashes() {  # build dir, [emulator...] -> the hashes the golden tests print
  local dir=$1; shift
  for t in test_golden_synthetic test_golden_recordings; do
    [ -x "$dir/tests/golden/$t" ] && BOLO_GOLDEN_PRINT=1 "$@" "$dir/tests/golden/$t" 2>/dev/null |
      grep -E '^[A-Za-z0-9_:.-]+ [0-9a-f]{16}$' || true
  done
}

if [ ! -x build/tests/golden/test_golden_synthetic ]; then
  echo "cross-test: build the host first (scripts/build.sh)" >&2
  exit 2
fi
golden_hashes build > build/golden-x86_64.txt

status=0
for target in "${targets[@]}"; do
  case $target in
    aarch64) toolchain=toolchain/aarch64-linux-gnu.cmake; emulator=(qemu-aarch64 -L /usr/aarch64-linux-gnu)
      build_targets=(all); test_filter=() ;;
    armhf) toolchain=toolchain/arm-linux-gnueabihf.cmake; emulator=(qemu-arm -L /usr/arm-linux-gnueabihf)
      build_targets=(test_fixed_point test_firmware test_vo_board test_golden_synthetic test_golden_recordings)
      test_filter=(-R "^(test_fixed_point|test_firmware|test_vo_board|test_golden_)") ;;
    *) echo "cross-test: unknown target '$target' (aarch64, armhf)" >&2; exit 2 ;;
  esac
  dir=build-$target
  echo "== $target: configure, build, test under ${emulator[0]}"
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DBOLO_BUILD_HOST_TOOLS=OFF -DBOLO_WERROR=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
  if [ "${build_targets[*]}" != all ]; then  # the ones this configuration defines
    available=$(ninja -C "$dir" -t targets all)
    mapfile -t build_targets < <(for t in "${build_targets[@]}"; do grep -q "^$t:" <<<"$available" && echo "$t"; done)
  fi
  cmake --build "$dir" -j "$jobs" --target "${build_targets[@]}"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" "${test_filter[@]}" || status=1
  golden_hashes "$dir" "${emulator[@]}" > "$dir/golden-$target.txt"
  if [ -s "$dir/golden-$target.txt" ] && diff -q build/golden-x86_64.txt "$dir/golden-$target.txt" >/dev/null; then
    echo "== $target: $(wc -l < "$dir/golden-$target.txt") golden hashes identical to x86-64"
  else
    echo "== $target: golden hashes DIFFER from x86-64:" >&2
    diff build/golden-x86_64.txt "$dir/golden-$target.txt" | head -20 >&2 || true
    status=1
  fi
done
exit $status
