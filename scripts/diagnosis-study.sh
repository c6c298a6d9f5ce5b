#!/usr/bin/env bash
# Regenerates docs/diagnosis-study.md and docs/diagnosis-injection-recovery.svg: builds `bolo`,
# makes every null, concealed and injection-recovery recording with `bolo simulate` and the second
# generator's recordings with scripts/study/independent_generator.py (no bolo code; needs NumPy),
# diagnoses them and the shared real recordings (../shared/data/real, when present) with
# `bolo diagnose`, and scores the findings against truth/ (scripts/diagnosis_study.py). About 330
# runs: 1-1.5 h on one core. `--quick` runs a small version (a few minutes); `--independent-only`
# runs only the second generator (~40 min; `--resume` keeps the runs already made; `--jobs 2`
# runs two of its recordings at a time);
# `--no-independent` leaves it out. `--concealed-only`, `--curves-only` (injection-recovery) and
# `--real-only` rerun that part and keep the rest of out/diagnosis-study/study.json. Work files go
# to out/diagnosis-study.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target bolo
work="$here/out/diagnosis-study"
mkdir -p "$work"
export BOLO_REAL="${BOLO_REAL:-$here/../shared/data/real}"
# The generator needs NumPy (Debian python3-numpy, scripts/deps.sh); a python3 first on PATH
# without it (a virtualenv, pyenv) gives way to the system's.
python=python3
if ! "$python" -c 'import numpy' 2>/dev/null && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  python=/usr/bin/python3
fi
export BOLO_NUMPY_PYTHON="${BOLO_NUMPY_PYTHON:-$python}"
"$python" "$here/scripts/diagnosis_study.py" "$build/apps/bolo" "$work" "$here/docs" "$@"
echo "wrote $here/docs/diagnosis-study.md"
