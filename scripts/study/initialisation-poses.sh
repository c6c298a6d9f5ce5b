#!/usr/bin/env bash
# What posing the initialisation's frames once it completes buys and costs: every run of `none`
# and `ir-loop` with the default output and with --online-poses-only, over ten seeds per cell
# (drives and handheld walks at 60 and 30 Hz, tau 10 ms; street, 160x120, noise 3, 3x3 rays, 4 s,
# rendered as ir-gain.sh renders them, so its WORK is reused). Writes WORK/index-init-poses.txt
# and the table OUT_MD (scripts/study/init_poses_table.py; default
# docs/odometry-study/initialisation-poses.md).
#
#   scripts/study/initialisation-poses.sh BOLO WORK [OUT_MD]
#
# Environment: CELLS ("drive:60 handheld:60 drive:30 handheld:30"), SEEDS (1 .. 10), SIZE
# (160x120), TAU (0.010), MODES (none ir-loop), JOBS (1).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: initialisation-poses.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/initialisation-poses.md}
CELLS="${CELLS:-drive:60 handheld:60 drive:30 handheld:30}"
SEEDS="${SEEDS:-1 2 3 4 5 6 7 8 9 10}"
SIZE="${SIZE:-160x120}"
TAU="${TAU:-0.010}"
MODES="${MODES:-none ir-loop}"
mkdir -p "$work"
index="$work/index-init-poses.txt"
jobs_file="$work/jobs-init-poses.txt"
: > "$index"
: > "$jobs_file"
for cell in $CELLS; do
  IFS=: read -r traj fps <<< "$cell"
  for seed in $SEEDS; do
    seq="$work/seq-$traj-$SIZE-${fps}hz-tau$TAU-ss3-s$seed"
    if [ ! -d "$seq" ]; then
      "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$fps" --frames $(( 4 * fps )) \
        --size "$SIZE" --tau "$TAU" --noise 3 --seed "$seed" --supersample 3 > /dev/null
      printf r >&2
    fi
    for mode in $MODES; do
      echo "$seq $mode $seq-init-$mode" >> "$jobs_file"
      echo "$seq $mode $seq-online-$mode --online-poses-only" >> "$jobs_file"
      echo "$traj $fps $seed $mode $seq-init-$mode $seq-online-$mode" >> "$index"
    done
  done
done
echo >&2
echo "initialisation-poses: $(wc -l < "$jobs_file") runs" >&2
JOBS="${JOBS:-1}" "$here/scripts/study/run-jobs.sh" "$bolo" "$jobs_file"
/usr/bin/python3 "$here/scripts/study/init_poses_table.py" "$index" "$out_md" \
  "street, $SIZE, tau $TAU s, noise 3 counts, 3 x 3 rays a pixel, 4 s, seeds $SEEDS"
echo "initialisation-poses: wrote $out_md" >&2
