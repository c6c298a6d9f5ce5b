#!/usr/bin/env bash
# How the map's scale follows the carry-over correction's tau: the IR modes with tau held at each
# of TAUS (--fixed-tau --tau-init T), then error_axes.py over every run (its drift column: the
# scale's slope over time). Writes WORK/index-drift.txt and the table OUT_MD.
#
#   scripts/study/tau-scale-drift.sh BOLO WORK OUT_MD
#
# The sequences are those of a finished dso-side-by-side.sh run in WORK, whose runs join the
# table (lag-time.sh's index-time.txt where it is there, so tau held at the truth is in it;
# otherwise index-dso.txt). With SEQUENCES (sequence folders, e.g. "$WORK"/seq-*-s?) they are
# those instead, each also run with tau estimated. Environment: TAUS (0.007 0.013 0.016, seconds),
# MODES (ir ir-loop), NOTE (the table's description of the sequences). Runs already done are kept
# unless REDO=1.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: tau-scale-drift.sh BOLO WORK OUT_MD" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
# shellcheck source=scripts/study/sequence-name.sh
. "$here/scripts/study/sequence-name.sh"
bolo=$(realpath "$1"); work=$(realpath "$2"); out_md=$(realpath -m "$3")
TAUS="${TAUS:-0.007 0.013 0.016}"
MODES="${MODES:-ir ir-loop}"
NOTE="${NOTE:-$(basename "$work")}"
index="$work/index-drift.txt"

run_once() {  # SEQ MODE RUN [options]: run-vo.sh unless the run is there
  local seq=$1 mode=$2 run=$3
  shift 3
  if [ "${REDO:-0}" = 1 ] || [ ! -f "$run/summary.json" ]; then
    "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run" "$@" || true
  fi
  printf . >&2
}

if [ -n "${SEQUENCES:-}" ]; then
  : > "$index"
  for seq in $SEQUENCES; do
    seq=$(cd "$seq" && pwd)  # the name given (a link stays a link: the runs go beside it)
    name=$(basename "$seq")
    traj=$(echo "$name" | cut -d- -f2)
    echo "$traj ${name##*-s} $seq"
  done
else
  base="$work/index-time.txt"
  [ -f "$base" ] || base="$work/index-dso.txt"
  [ -f "$base" ] || { echo "tau-scale-drift: $work/index-dso.txt: run dso-side-by-side.sh first, or set SEQUENCES" >&2; exit 2; }
  cp "$base" "$index"
  study_index_sequences "$base"
fi | while read -r traj seed seq; do
  for mode in $MODES; do
    if [ -n "${SEQUENCES:-}" ]; then
      run_once "$seq" "$mode" "$seq-vo-$mode"
      echo "$traj $seed $mode - - $seq-vo-$mode" >> "$index"
    fi
    for tau in $TAUS; do
      ms=$(awk -v t="$tau" 'BEGIN { printf "%g", t * 1000 }')
      run="$seq-vo-$mode-tau-$ms-ms"
      run_once "$seq" "$mode" "$run" --fixed-tau --tau-init "$tau"
      echo "$traj $seed $mode-tau-$ms-ms - - $run" >> "$index"
    done
  done
done
echo >&2
/usr/bin/python3 -B "$here/scripts/study/error_axes.py" "$index" "$out_md" "$NOTE"
