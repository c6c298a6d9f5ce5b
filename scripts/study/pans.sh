#!/usr/bin/env bash
# Rotation about the camera's centre: street pans (bolo simulate --trajectory pan, 30 deg/s) at
# 160x120 and 320x256, 9, 15, 30 and 60 Hz, one ray and 3x3 rays a pixel, through bolo odometry in every
# mode. A pan gives no baseline, so it measures how the VO initialises and tracks while no point
# can be triangulated. Beyond 4 s (120 degrees) the pan faces a blank wall, where nothing tracks. Writes WORK/index-pans.txt and the table OUT_MD (scripts/study/pan_table.py;
# default docs/odometry-study/pans.md).
#
#   scripts/study/pans.sh BOLO WORK [OUT_MD]
#
# Environment: CONFIGS ("60:160x120:3 60:160x120:1 30:160x120:3 15:160x120:3 9:160x120:3
# 60:320x256:3": FPS:SIZE:RAYS),
# SEEDS (1 2 3 4 5 6), TAU (0.010), NOISE (3), SECONDS_LONG (4), MODES, TAG (a suffix of the run
# folders, to keep the runs of two builds apart). Sequences already in WORK are reused; runs are
# redone. Two runs at a time.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: pans.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/pans.md}
CONFIGS="${CONFIGS:-60:160x120:3 60:160x120:1 30:160x120:3 15:160x120:3 9:160x120:3 60:320x256:3}"
SEEDS="${SEEDS:-1 2 3 4 5 6}"
TAU="${TAU:-0.010}"
NOISE="${NOISE:-3}"
SECONDS_LONG="${SECONDS_LONG:-4}"
MODES="${MODES:-none affine ir ir-loop}"
TAG="${TAG:-}"
mkdir -p "$work"
: > "$work/index-pans.txt"
jobs_file="$work/jobs-pans.txt"
: > "$jobs_file"
for config in $CONFIGS; do
  IFS=: read -r fps size rays <<< "$config"
  for seed in $SEEDS; do
    seq="$work/pan-${fps}hz-$size-ss$rays-s$seed"
    if [ ! -d "$seq" ]; then
      "$bolo" simulate "$seq" --scene street --trajectory pan --fps "$fps" --frames $(( SECONDS_LONG * fps )) \
        --size "$size" --tau "$TAU" --noise "$NOISE" --seed "$seed" --supersample "$rays" > /dev/null
    fi
    for mode in $MODES; do
      echo "$seq $mode $seq-vo-$mode$TAG" >> "$jobs_file"
      echo "$fps $size $rays $seed $mode $seq-vo-$mode$TAG" >> "$work/index-pans.txt"
    done
  done
done
echo "pans: $(wc -l < "$jobs_file") runs, two at a time" >&2
JOBS=2 "$here/scripts/study/run-jobs.sh" "$bolo" "$jobs_file"
python3 "$here/scripts/study/pan_table.py" "$work/index-pans.txt" "$out_md"
echo "pans: wrote $out_md" >&2
