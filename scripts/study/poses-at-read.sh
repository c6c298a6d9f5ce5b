#!/usr/bin/env bash
# `bolo odometry --poses-at-read` before and after, on a finished lag-time.sh WORK (continuous-lag
# renders, whose t_s is the read instant): `ir` and `ir-loop`, and `ir-loop` with tau held at the
# truth, each again with --poses-at-read, all scored by lag_time_table.py (ATE by time shift, the
# instant the orientations stand for). Writes WORK/index-read.txt and OUT_MD.
#
#   scripts/study/poses-at-read.sh BOLO WORK OUT_MD
#
# Environment: TAU (0.010), the rendered tau; SHIFTS_MS (-4 0 4 8); NOTE. Runs already done are
# kept unless REDO=1.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: poses-at-read.sh BOLO WORK OUT_MD" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath "$2"); out_md=$(realpath -m "$3")
TAU="${TAU:-0.010}"
[ -f "$work/index-time.txt" ] || { echo "poses-at-read: $work/index-time.txt: run lag-time.sh first" >&2; exit 2; }
index="$work/index-read.txt"
: > "$index"
awk '$3 == "ir-loop-tau-held" { seq = $6; sub(/-vo-ir-loop-tau-held$/, "", seq); print $1, $2, seq }' \
  "$work/index-time.txt" | while read -r traj seed seq; do
  for mode in ir ir-loop; do
    if [ "${REDO:-0}" = 1 ] || [ ! -f "$seq-vo-$mode-read/summary.json" ]; then
      "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$seq-vo-$mode-read" --poses-at-read || true
    fi
    echo "$traj $seed $mode - - $seq-vo-$mode" >> "$index"
    echo "$traj $seed $mode-poses-at-read - - $seq-vo-$mode-read" >> "$index"
  done
  if [ "${REDO:-0}" = 1 ] || [ ! -f "$seq-vo-ir-loop-tau-held-read/summary.json" ]; then
    "$here/scripts/study/run-vo.sh" "$bolo" "$seq" ir-loop "$seq-vo-ir-loop-tau-held-read" --poses-at-read \
      --fixed-tau --tau-init "$TAU" || true
  fi
  echo "$traj $seed ir-loop-tau-held - - $seq-vo-ir-loop-tau-held" >> "$index"
  echo "$traj $seed ir-loop-tau-held-poses-at-read - - $seq-vo-ir-loop-tau-held-read" >> "$index"
  printf . >&2
done
echo >&2
GENERATOR=scripts/study/poses-at-read.sh /usr/bin/python3 -B "$here/scripts/study/lag_time_table.py" "$bolo" "$index" "$out_md" "${NOTE:-$(basename "$work")}" \
  "${SHIFTS_MS:--4 0 4 8}"
