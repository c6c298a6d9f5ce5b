#!/usr/bin/env bash
# Checks the DSO peer's harness apart from DSO's results on the study's renders: DSO on two
# recordings any working direct VO tracks (scripts/study/dso_harness_check.py: a camera sliding
# sideways and one moving ahead over a textured plane, no noise), scored by dso-run.sh as in the
# study. Prints each run's posed share and ATE; exit 1 when either misses 0.5 % of the path.
#
#   scripts/study/dso-harness-check.sh BOLO DSO_DATASET WORK
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: dso-harness-check.sh BOLO DSO_DATASET WORK" >&2; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
bolo=$(realpath "$1"); dso=$(realpath "$2"); work=$(realpath -m "$3")
/usr/bin/python3 "$here/dso_harness_check.py" make "$work"
status=0
for motion in sideways forward; do
  "$here/dso-run.sh" "$bolo" "$dso" "$work/$motion" "$work/$motion-dso" || true
  /usr/bin/python3 "$here/dso_harness_check.py" score "$work/$motion-dso" || status=1
done
exit $status
