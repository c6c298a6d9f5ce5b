#!/usr/bin/env bash
# Sanitizer run for CI: builds the `asan` preset (clang, AddressSanitizer + UndefinedBehaviorSanitizer,
# -O2 -g1, errors fatal, libraries coverage-instrumented for the fuzz targets that
# scripts/fuzz-smoke.sh runs from the same build) into build-asan and runs the host test suite
# there, the fuzz corpus and regression replays included, the VO's long accuracy tests (label
# vo-long) left out; then the
# `tsan` preset (ThreadSanitizer) on the threaded code. See docs/hardening.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$(nproc)"
status=0
ctest --preset asan -j "$(nproc)" || status=1
# ThreadSanitizer on the code that starts threads (the scene renderer's pool; its tests render
# with 1 to 7 threads and compare bit for bit). Everything else is single-threaded.
cmake --preset tsan >/dev/null
cmake --build --preset tsan -j "$(nproc)"
ctest --preset tsan -j "$(nproc)" || status=1
exit $status
