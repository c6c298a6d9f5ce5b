#!/usr/bin/env bash
# Sanitizer run for CI: builds the `asan` preset (gcc, AddressSanitizer + UndefinedBehaviorSanitizer,
# RelWithDebInfo, errors fatal) into build-asan and runs the whole host test suite there, the
# fuzz corpus and regression replays included. See docs/hardening.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$(nproc)"
ctest --preset asan -j "$(nproc)"
