#!/usr/bin/env bash
# Does the IR model pay, and never cost? Issue 41's ask 2: `ir-loop` (and `ir`) against `none`
# over ten seeds per cell: drives at tau 10 and 15 ms, handheld walks (look-arounds turning at
# 180-560 deg/s) and both at 30 Hz; street, 320x256, noise 3, 3x3 rays, 4 s. Writes
# WORK/index-ir-gain.txt and the table OUT_MD (scripts/study/ir_gain_table.py; default
# docs/odometry-study/ir-gain.md).
#
#   scripts/study/ir-gain.sh BOLO WORK [OUT_MD]
#
# Environment: CELLS ("drive:60:0.010 drive:60:0.015 handheld:60:0.010 drive:30:0.010
# handheld:30:0.010": TRAJECTORY:FPS:TAU), SEEDS (1 .. 10), SIZE (320x256), NOISE (3),
# SUPERSAMPLE (3), SECONDS_LONG (4), MODES (none ir ir-loop), JOBS (1). Sequences already in WORK
# are reused; runs are redone unless KEEP_DONE=1.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: ir-gain.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/ir-gain.md}
CELLS="${CELLS:-drive:60:0.010 drive:60:0.015 handheld:60:0.010 drive:30:0.010 handheld:30:0.010}"
SEEDS="${SEEDS:-1 2 3 4 5 6 7 8 9 10}"
SIZE="${SIZE:-320x256}"
NOISE="${NOISE:-3}"
SUPERSAMPLE="${SUPERSAMPLE:-3}"
SECONDS_LONG="${SECONDS_LONG:-4}"
MODES="${MODES:-none ir ir-loop}"
# shellcheck source=scripts/study/sequence-name.sh
. "$here/scripts/study/sequence-name.sh"
mkdir -p "$work"
index="$work/index-ir-gain.txt"
jobs_file="$work/jobs-ir-gain.txt"
: > "$index"
: > "$jobs_file"
for cell in $CELLS; do
  IFS=: read -r traj fps tau <<< "$cell"
  for seed in $SEEDS; do
    seq=$(study_sequence "$work" "$traj" "$SIZE" "$fps" "$tau" "$SUPERSAMPLE" exposure-readout "" "$seed")
    if [ ! -d "$seq" ]; then
      "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$fps" --frames $(( SECONDS_LONG * fps )) \
        --size "$SIZE" --tau "$tau" --noise "$NOISE" --seed "$seed" --supersample "$SUPERSAMPLE" > /dev/null
      printf r >&2
    fi
    for mode in $MODES; do
      echo "$seq $mode $seq-vo-$mode" >> "$jobs_file"
      echo "$traj $fps $tau $seed $mode $seq-vo-$mode" >> "$index"
    done
  done
done
echo >&2
echo "ir-gain: $(wc -l < "$jobs_file") runs" >&2
JOBS="${JOBS:-1}" "$here/scripts/study/run-jobs.sh" "$bolo" "$jobs_file"
/usr/bin/python3 "$here/scripts/study/ir_gain_table.py" "$index" "$out_md" \
  "street, $SIZE, noise $NOISE counts, $SUPERSAMPLE x $SUPERSAMPLE rays a pixel, $SECONDS_LONG s, seeds $SEEDS"
echo "ir-gain: wrote $out_md" >&2
