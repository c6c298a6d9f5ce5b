#!/usr/bin/env bash
# Test command: installs what is missing, builds (unity builds throughout: CI compiles cold), then
#   - in the background, the hardware-in-loop VMs one after another: the arm64 suite
#     (toolchain/vm/hil-arm64.sh) then x86-64's (ctest label `hil`); docs/hil.md;
#   - beside them:
#     1. the board parts for aarch64 and armhf, tested under qemu-user, golden hashes compared
#        bit for bit with x86-64 (scripts/cross-test.sh);
#     2. static analysis of firmware/, fixed_point/, hal/ and the layers check
#        (scripts/static-analysis.sh);
#     3. the host suite under AddressSanitizer + UBSan, and the threaded code under TSan
#        (scripts/sanitize.sh);
#     4. every fuzz target for a short fixed time, from the sanitizer stage's build
#        (scripts/fuzz-smoke.sh);
#     5. the host test suite without the VMs.
# Ends with each stage's wall time and the failed stages, if any.
set -uo pipefail
cd "$(dirname "$0")/.."
failed=()
timings=()
start=$SECONDS
scripts/deps.sh || exit 1
timings+=("deps $((SECONDS - start)) s")
start=$SECONDS
scripts/build.sh || exit 1
timings+=("build $((SECONDS - start)) s")

# The VMs run beside the CPU-bound stages rather than after them: the arm64 suite starts with
# downloads and a VM waits on the emulated devices' timing most of the time. They keep the normal
# priority and the stages run niced: a VM starved of CPU stretches every timeout it waits on and
# burns more CPU in all. One chain: the VMs share the kernel cache.
hil_dir=$(mktemp -d)
trap 'rm -rf "$hil_dir"' EXIT
(
  start=$SECONDS
  toolchain/vm/hil-arm64.sh && touch "$hil_dir/arm64.ok"
  echo "hil-arm64 $((SECONDS - start)) s" > "$hil_dir/arm64.time"
  start=$SECONDS
  ctest --test-dir build -L '^hil$' --output-on-failure && touch "$hil_dir/x86_64.ok"
  echo "hil-x86_64 $((SECONDS - start)) s" > "$hil_dir/x86_64.time"
) > "$hil_dir/log" 2>&1 &
hil_pid=$!

# Runs one stage (niced, below the VMs), records its wall time for the summary, and notes it when
# it fails.
stage() {
  local name=$1 start=$SECONDS
  shift
  nice -n 10 "$@" || failed+=("$name")
  timings+=("$name $((SECONDS - start)) s")
}
stage cross-test scripts/cross-test.sh
stage static-analysis scripts/static-analysis.sh
stage sanitize scripts/sanitize.sh
stage fuzz-smoke scripts/fuzz-smoke.sh
stage host-suite ctest --test-dir build -LE '^hil' --output-on-failure -j "$(nproc)"

start=$SECONDS
wait "$hil_pid"
timings+=("waiting for the VMs $((SECONDS - start)) s")
echo "== hardware-in-loop (the arm64 VM, then the x86-64 VMs):"
cat "$hil_dir/log"
for arch in arm64 x86_64; do
  [ -f "$hil_dir/$arch.time" ] && timings+=("$(cat "$hil_dir/$arch.time") (background)")
  [ -f "$hil_dir/$arch.ok" ] || failed+=("hil-$arch")
done
echo "test.sh: stage times: $(IFS=,; echo "${timings[*]}" | sed 's/,/, /g'); ${SECONDS} s in all"
[ ${#failed[@]} -eq 0 ] || { echo "test.sh: failed: ${failed[*]} (see above)" >&2; exit 1; }
echo "test.sh: every stage passed"
