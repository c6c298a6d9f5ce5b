#!/usr/bin/env bash
# Where bolo's accuracy goes on a set of dso-side-by-side.sh runs: the IR modes again with tau held
# at the truth (--fixed-tau --tau-init TAU), then every run (bolo's, DSO's, the held-tau ones)
# scored against the truth shifted in time (lag_time_table.py): which instant the poses stand
# for, and whether it costs ATE or RPE. Writes WORK/index-time.txt and the table OUT_MD.
#
#   scripts/study/lag-time.sh BOLO WORK OUT_MD
#
# WORK holds a finished dso-side-by-side.sh run (index-dso.txt). Environment: TAU (0.010), the
# rendered tau; FIXED_MODES (ir ir-loop); SHIFTS_MS (-4 0 4 8 12); NOTE (the table's
# description of the sequences). Held-tau runs already done are kept unless REDO=1.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: lag-time.sh BOLO WORK OUT_MD" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
# shellcheck source=scripts/study/sequence-name.sh
. "$here/scripts/study/sequence-name.sh"
bolo=$(realpath "$1"); work=$(realpath "$2"); out_md=$(realpath -m "$3")
TAU="${TAU:-0.010}"
FIXED_MODES="${FIXED_MODES:-ir ir-loop}"
SHIFTS_MS="${SHIFTS_MS:--4 0 4 8 12}"
NOTE="${NOTE:-$(basename "$work")}"
[ -f "$work/index-dso.txt" ] || { echo "lag-time: $work/index-dso.txt: run dso-side-by-side.sh first" >&2; exit 2; }
index="$work/index-time.txt"
cp "$work/index-dso.txt" "$index"
study_index_sequences "$work/index-dso.txt" | while read -r traj seed seq; do
  for mode in $FIXED_MODES; do
    run="$seq-vo-$mode-tau-held"
    if [ "${REDO:-0}" = 1 ] || [ ! -f "$run/summary.json" ]; then
      "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run" --fixed-tau --tau-init "$TAU" || true
    fi
    echo "$traj $seed $mode-tau-held - - $run" >> "$index"
    printf . >&2
  done
done
echo >&2
/usr/bin/python3 -B "$here/scripts/study/lag_time_table.py" "$bolo" "$index" "$out_md" "$NOTE" "$SHIFTS_MS"
