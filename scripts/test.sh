#!/usr/bin/env bash
# Test command: installs what is missing, builds, builds the board parts for aarch64 and armhf
# and runs their tests under qemu-user (checking that the golden hashes agree bit for bit with
# x86-64), then runs the whole host test suite with ctest, whose summary ends the output.
set -uo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh || exit 1
scripts/build.sh || exit 1
scripts/cross-test.sh
cross=$?
ctest --test-dir build --output-on-failure -j "$(nproc)"
host=$?
[ $cross -eq 0 ] || echo "test.sh: the aarch64/armhf tests failed (see above)" >&2
[ $cross -eq 0 ] && [ $host -eq 0 ]
