#!/usr/bin/env bash
# Configures and builds bolo into ./build: the `release` preset (Release, Ninja, -Werror on the
# board code, unity build).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
