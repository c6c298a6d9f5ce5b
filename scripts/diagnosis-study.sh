#!/usr/bin/env bash
# Regenerates docs/diagnosis-study.md and docs/diagnosis-injection-recovery.svg: builds `bolo`,
# makes every null, concealed and injection-recovery recording with `bolo simulate`, diagnoses
# them and the shared real recordings (../shared/data/real, when present) with `bolo diagnose`,
# and scores the findings against truth/ (scripts/diagnosis_study.py). About 250 runs: 15-40 min
# on one core. `--quick` runs a small version (a few minutes). Work files go to out/diagnosis-study.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target bolo
work="$here/out/diagnosis-study"
mkdir -p "$work"
export BOLO_REAL="${BOLO_REAL:-$here/../shared/data/real}"
python3 "$here/scripts/diagnosis_study.py" "$build/apps/bolo" "$work" "$here/docs" "$@"
echo "wrote $here/docs/diagnosis-study.md"
