#!/usr/bin/env bash
# Builds what runs on a camera board (fixed_point, the core, firmware, hal with its recording I/O,
# their tests) for aarch64 and armhf with Debian's cross compilers, runs the tests under qemu-user,
# and checks that the golden hashes printed on each target are identical to the host's.
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
    aarch64) toolchain=toolchain/aarch64-linux-gnu.cmake; emulator=(qemu-aarch64 -L /usr/aarch64-linux-gnu) ;;
    armhf) toolchain=toolchain/arm-linux-gnueabihf.cmake; emulator=(qemu-arm -L /usr/arm-linux-gnueabihf) ;;
    *) echo "cross-test: unknown target '$target' (aarch64, armhf)" >&2; exit 2 ;;
  esac
  dir=build-$target
  echo "== $target: configure, build, test under ${emulator[0]}"
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DBOLO_BUILD_HOST_TOOLS=OFF -DBOLO_WERROR=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" || status=1
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
