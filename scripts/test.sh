#!/usr/bin/env bash
# Test command: installs what is missing, builds (unity builds throughout: CI compiles cold), then
#   1. the board parts for aarch64 and armhf, tested under qemu-user, golden hashes compared
#      bit for bit with x86-64 (scripts/cross-test.sh);
#   2. the host suite under AddressSanitizer + UBSan, and the threaded code under TSan
#      (scripts/sanitize.sh);
#   3. the hardware-in-loop suite in an arm64 VM (toolchain/vm/hil-arm64.sh; docs/hil.md), and
#      beside it, at the lowest CPU priority, every fuzz target for a short fixed time from the
#      sanitizer stage's build (scripts/fuzz-smoke.sh), then static analysis of firmware/,
#      fixed_point/, hal/ and the layers check (scripts/static-analysis.sh);
#   4. the host test suite, the x86-64 HIL VMs one at a time beside the rest (the steps the arm64
#      VM passed are left out there).
# Ends with each stage's wall time and the failed stages, if any.
set -uo pipefail
cd "$(dirname "$0")/.."
failed=()
timings=()
start=$SECONDS
scripts/deps.sh || exit 1
timings+=("deps $((SECONDS - start)) s")

# The VMs' downloads (the arm64 sysroot, both kernels) run in the background from here: network
# time beside the builds. The VM stages wait for them. The VMs themselves run alone: a TCG VM
# starved of CPU stretches every timeout it waits on and costs more CPU in all.
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
(
  toolchain/vm/arm64-sysroot.sh >/dev/null
  # shellcheck source=../toolchain/vm/kernel-cache.sh
  source toolchain/vm/kernel-cache.sh
  for arch in aarch64 x86_64; do
    hil_kernel_dir "$arch" "${BOLO_HIL_CACHE:-$HOME/.cache/bolo-hil}" >/dev/null
  done
) > "$logs/hil-downloads.log" 2>&1 &
downloads=$!

start=$SECONDS
scripts/build.sh || exit 1
timings+=("build $((SECONDS - start)) s")

# Runs one stage, records its wall time for the summary, and notes it when it fails.
stage() {
  local name=$1 start=$SECONDS
  shift
  "$@" || failed+=("$name")
  timings+=("$name $((SECONDS - start)) s")
}
stage cross-test scripts/cross-test.sh
stage sanitize scripts/sanitize.sh
# The arm64 VM waits on its emulated devices most of the time and leaves about a core idle: the
# fuzz smoke and the static analysis run beside it at the lowest CPU priority, so they take no
# CPU the VM wants; their output is printed when the VM stage has ended.
beside_arm64() {  # name command...: runs niced, leaves NAME.log, NAME.status, NAME.seconds in $logs
  local name=$1 start=$SECONDS
  shift
  nice -n 19 "$@" >"$logs/$name.log" 2>&1
  echo $? >"$logs/$name.status"
  echo $((SECONDS - start)) >"$logs/$name.seconds"
}
(beside_arm64 fuzz-smoke scripts/fuzz-smoke.sh; beside_arm64 static-analysis scripts/static-analysis.sh) &
beside=$!
# A failed download is not fatal here: the HIL stages fetch what is missing and say what failed.
wait "$downloads" || cat "$logs/hil-downloads.log" >&2
stage hil-arm64 toolchain/vm/hil-arm64.sh
start=$SECONDS
wait "$beside"
for name in fuzz-smoke static-analysis; do
  cat "$logs/$name.log"
  [ "$(cat "$logs/$name.status" 2>/dev/null)" = 0 ] || failed+=("$name")
  timings+=("$name $(cat "$logs/$name.seconds" 2>/dev/null) s (beside hil-arm64)")
done
timings+=("after hil-arm64 $((SECONDS - start)) s")
# The steps the arm64 VM passed (USB streaming, faults and replugs of the FLIR ONE and the UVC
# camera) are not repeated on x86-64; its VMs run the rest (the CLI, v4l2loopback, Seek, GPIO).
arm64_log=build-hil-arm64/Testing/Temporary/LastTest.log
if [[ " ${failed[*]} " != *" hil-arm64 "* ]] && [ -f "$arm64_log" ]; then
  BOLO_HIL_SKIP_STEPS=$(sed -n 's/^HIL-STEP \([a-z0-9_]*\) end .*/\1/p' "$arm64_log" | sort -u | tr '\n' ' ')
  export BOLO_HIL_SKIP_STEPS
  echo "test.sh: x86-64 HIL leaves out what the arm64 VM passed: $BOLO_HIL_SKIP_STEPS"
fi
stage host-suite ctest --test-dir build --output-on-failure -j "$(nproc)"

echo "test.sh: stage times: $(IFS=,; echo "${timings[*]}" | sed 's/,/, /g'); ${SECONDS} s in all"
if [ ${#failed[@]} -gt 0 ]; then
  # A stage run beside the VM printed its log far above; its end is repeated here, where a
  # truncated CI log still shows it.
  for name in "${failed[@]}"; do
    [ -f "$logs/$name.log" ] || continue
    echo "== the end of $name's log (exit $(cat "$logs/$name.status" 2>/dev/null))"
    tail -n 40 "$logs/$name.log"
  done
  echo "test.sh: failed: ${failed[*]} (see above)" >&2
  exit 1
fi
echo "test.sh: every stage passed"
