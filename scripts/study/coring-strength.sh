#!/usr/bin/env bash
# How much the IR modes' accuracy depends on the coring of the carry-over correction
# (bolo odometry --carry-coring K) now that the tracking image is low-passed: street sequences at
# several noise levels and frame rates, one ray and 3x3 rays a pixel, every mode at the defaults,
# then ir and ir-loop again at each K of KS. CONTROL is a K a hair from the default: the runs are
# chaotic, and what a change that small moves is what any change moves by chance. Writes
# WORK/index-coring.txt and the tables OUT_MD (scripts/study/coring_table.py; default
# docs/odometry-study/coring-strength.md).
#
#   scripts/study/coring-strength.sh BOLO WORK [OUT_MD]
#
# Environment: SETS ("60:1 60:6 30:3": FPS:NOISE pairs), TRAJECTORIES (drive handheld), TAU (0.012),
# SEEDS (1 2 3 4 5 6), RAYS (1 3), KS (0 0.5 1.5), CONTROL (1.001), SECONDS_LONG (4), SIZE
# (160x120). EXTRA_SEQUENCES: recordings rendered elsewhere to add to the set (e.g. the study's
# six-seed sequences; their label is their folder's name up to "-s<seed>"). Sequences and runs
# already in WORK are reused (remove WORK to rerun with a new build). Two runs at a time.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: coring-strength.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/coring-strength.md}
SETS="${SETS:-60:1 60:6 30:3}"
TRAJECTORIES="${TRAJECTORIES:-drive handheld}"
TAU="${TAU:-0.012}"
SEEDS="${SEEDS:-1 2 3 4 5 6}"
RAYS="${RAYS:-1 3}"
KS="${KS:-0 0.5 1.5}"
CONTROL="${CONTROL:-1.001}"
SECONDS_LONG="${SECONDS_LONG:-4}"
SIZE="${SIZE:-160x120}"
mkdir -p "$work"
sequences=()
for set in $SETS; do
  fps=${set%%:*} noise=${set##*:}
  for traj in $TRAJECTORIES; do
    for seed in $SEEDS; do
      for rays in $RAYS; do
        seq="$work/seq-$traj-${fps}hz-n$noise-s$seed-ss$rays"
        if [ ! -d "$seq" ]; then
          "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$fps" --frames $(( SECONDS_LONG * fps )) \
            --size "$SIZE" --tau "$TAU" --noise "$noise" --seed "$seed" --supersample "$rays" > /dev/null
        fi
        sequences+=("$seq")
      done
    done
  done
done
for seq in ${EXTRA_SEQUENCES:-}; do sequences+=("$(realpath "$seq")"); done
echo "coring-strength: ${#sequences[@]} sequences" >&2
# One job a line: SEQ MODE RUN [options] (scripts/study/run-jobs.sh); runs whose evaluation exists are kept.
jobs_file="$work/jobs-coring.txt"
: > "$jobs_file"
for seq in "${sequences[@]}"; do
  for mode in none affine ir ir-loop; do echo "$seq $mode $seq-vo-$mode" >> "$jobs_file"; done
  for k in $KS $CONTROL; do
    for mode in ir ir-loop; do echo "$seq $mode $seq-vo-$mode-core$k --carry-coring $k" >> "$jobs_file"; done
  done
done
total=$(wc -l < "$jobs_file")
echo "coring-strength: $total runs (two at a time; existing ones kept)" >&2
KEEP_DONE=1 JOBS=2 "$here/scripts/study/run-jobs.sh" "$bolo" "$jobs_file"
printf '%s\n' "${sequences[@]}" > "$work/index-coring.txt"
python3 "$here/scripts/study/coring_table.py" "$work/index-coring.txt" "$out_md" --ks "$KS" --control "$CONTROL"
echo "coring-strength: wrote $out_md" >&2
