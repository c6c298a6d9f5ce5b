#!/usr/bin/env bash
# Slow cameras: street drives and walks (bolo simulate, 3x3 rays a pixel) at frame rates below the
# study's 30 / 60 Hz (default 9 Hz, the rate of export-free thermal cores, and 15 Hz), through
# bolo odometry in every mode. Writes WORK/index-rates.txt and the table OUT_MD
# (scripts/study/rates_table.py; default docs/odometry-study/frame-rates.md).
#
#   scripts/study/frame-rates.sh BOLO WORK [OUT_MD]
#
# Environment: RATES (9 15), TRAJECTORIES (drive handheld), SEEDS (1 2 3 4 5 6), SECONDS_LONG (8),
# SIZE (160x120), TAU (0.012), NOISE (3), MODES, TAG (a suffix of the run folders, to keep two
# builds' runs apart). Sequences already in WORK are reused; runs are redone. Two runs at a time.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: frame-rates.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/frame-rates.md}
RATES="${RATES:-9 15}"
TRAJECTORIES="${TRAJECTORIES:-drive handheld}"
SEEDS="${SEEDS:-1 2 3 4 5 6}"
SECONDS_LONG="${SECONDS_LONG:-8}"
SIZE="${SIZE:-160x120}"
TAU="${TAU:-0.012}"
NOISE="${NOISE:-3}"
MODES="${MODES:-none affine ir ir-loop}"
TAG="${TAG:-}"
mkdir -p "$work"
: > "$work/index-rates.txt"
jobs_file="$work/jobs-rates.txt"
: > "$jobs_file"
for fps in $RATES; do
  for traj in $TRAJECTORIES; do
    for seed in $SEEDS; do
      seq="$work/seq-$traj-${fps}hz-s$seed"
      if [ ! -d "$seq" ]; then
        "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$fps" --frames $(( SECONDS_LONG * fps )) \
          --size "$SIZE" --tau "$TAU" --noise "$NOISE" --seed "$seed" --supersample 3 > /dev/null
      fi
      for mode in $MODES; do
        echo "$seq $mode $seq-vo-$mode$TAG" >> "$jobs_file"
        echo "$fps $traj $seed $mode $seq-vo-$mode$TAG" >> "$work/index-rates.txt"
      done
    done
  done
done
echo "frame-rates: $(wc -l < "$jobs_file") runs, two at a time" >&2
JOBS=2 "$here/scripts/study/run-jobs.sh" "$bolo" "$jobs_file"
python3 "$here/scripts/study/rates_table.py" "$work/index-rates.txt" "$out_md"
echo "frame-rates: wrote $out_md" >&2
