#!/usr/bin/env bash
# Test command: installs what is missing, builds (unity builds throughout: CI compiles cold), then
#   1. the board parts for aarch64 and armhf, tested under qemu-user, golden hashes compared
#      bit for bit with x86-64 (scripts/cross-test.sh);
#   2. static analysis of firmware/, fixed_point/, hal/ and the layers check (scripts/static-analysis.sh);
#   3. the whole host suite under AddressSanitizer + UBSan, and the threaded code under TSan
#      (scripts/sanitize.sh);
#   4. every fuzz target for a short fixed time, from the sanitizer stage's build
#      (scripts/fuzz-smoke.sh);
#   4b. the hardware-in-loop suite in an arm64 VM (toolchain/vm/hil-arm64.sh; x86-64's runs in 5);
#   5. the whole host test suite, whose ctest summary ends the output.
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
# Runs one stage, records its wall time for the summary, and notes it when it fails.
stage() {
    local name=$1 start=$SECONDS
    shift
    "$@" || failed+=("$name")
    timings+=("$name $((SECONDS - start)) s")
}
stage cross-test scripts/cross-test.sh
stage static-analysis scripts/static-analysis.sh
stage sanitize scripts/sanitize.sh
stage fuzz-smoke scripts/fuzz-smoke.sh
stage hil-arm64 toolchain/vm/hil-arm64.sh   # the HIL suite in an arm64 VM (docs/hil.md)
echo "test.sh: stage times: $(IFS=,; echo "${timings[*]}" | sed 's/,/, /g'); ${SECONDS} s so far"
# The host suite last: its ctest summary ends the output (its own total time included).
ctest --test-dir build --output-on-failure -j "$(nproc)"
host=$?
[ ${#failed[@]} -eq 0 ] || echo "test.sh: failed: ${failed[*]} (see above)" >&2
[ ${#failed[@]} -eq 0 ] && [ $host -eq 0 ]
