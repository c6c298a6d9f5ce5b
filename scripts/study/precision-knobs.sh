#!/usr/bin/env bash
# Where bolo's accuracy goes against DSO's (issue 41, ask 1): the study's 10-s drives (street,
# 320x256, 60 Hz, tau 10 ms, noise 3, 3x3 rays), bolo `ir` with one setting changed at a time, and
# DSO on the paper's corrected frames at every third frame (its best variant in
# docs/odometry-study/dso-10s.md), all scored by bolo evaluate: ATE (drift included) against the
# one-second relative pose error (local precision, translation and rotation). Writes
# WORK/index-knobs.txt and the table OUT_MD (scripts/study/knobs_table.py; default
# docs/odometry-study/precision-knobs.md).
#
#   scripts/study/precision-knobs.sh BOLO DSO_DATASET WORK [OUT_MD]
#
# DSO_DATASET from scripts/study/dso-build.sh ("-" leaves DSO out). Environment: SEEDS (1 .. 5),
# SECONDS_LONG (10), TAU (0.010). Sequences already in WORK are reused.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: precision-knobs.sh BOLO DSO_DATASET WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); dso=$2; work=$(realpath -m "$3")
out_md=${4:-$here/docs/odometry-study/precision-knobs.md}
SEEDS="${SEEDS:-1 2 3 4 5}"
SECONDS_LONG="${SECONDS_LONG:-10}"
TAU="${TAU:-0.010}"
tau_low=$(awk -v t="$TAU" 'BEGIN { printf "%.6f", 0.92 * t }')
tau_high=$(awk -v t="$TAU" 'BEGIN { printf "%.6f", 1.08 * t }')
# NAME|MODE|bolo odometry options (one setting changed from the defaults each).
variants=(
  "ir|ir|"
  "none|none|"
  "ir, tau held at the truth|ir|--fixed-tau --tau-init $TAU"
  "ir, tau held 8 % low|ir|--fixed-tau --tau-init $tau_low"
  "ir, tau held 8 % high|ir|--fixed-tau --tau-init $tau_high"
  "ir, marginalisation prior|ir|--marginalisation-prior"
  "ir, 6 keyframes|ir|--max-keyframes 6"
  "ir, no low-pass|ir|--smoothing 0"
  "ir, two low-pass passes|ir|--smoothing 2"
  "ir, full carry-over correction|ir|--carry-coring 0"
  "ir, 1 000 points a keyframe|ir|--points-per-keyframe 1000"
  "ir, 1 000 points, tau held at the truth|ir|--points-per-keyframe 1000 --fixed-tau --tau-init $TAU"
  "none, 1 000 points a keyframe|none|--points-per-keyframe 1000"
)
mkdir -p "$work"
index="$work/index-knobs.txt"
: > "$index"
for seed in $SEEDS; do
  seq="$work/seq-drive-320x256-60hz-tau$TAU-ss3-s$seed"
  [ -d "$seq" ] || "$bolo" simulate "$seq" --scene street --trajectory drive --fps 60 --frames $(( SECONDS_LONG * 60 )) \
    --size 320x256 --tau "$TAU" --noise 3 --seed "$seed" --supersample 3 > /dev/null
  for i in "${!variants[@]}"; do
    IFS='|' read -r name mode options <<< "${variants[$i]}"
    run="$seq-knob$i"
    # shellcheck disable=SC2086
    "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run" $options || true
    echo "$seed|$name|$run" >> "$index"
    printf . >&2
  done
  if [ "$dso" != - ]; then
    [ -d "$seq-corrected" ] || "$bolo" correct "$seq" "$seq-corrected" --tau-h "$TAU" --tau-c "$TAU" --no-progress > /dev/null
    "$here/scripts/study/dso-run.sh" "$bolo" "$(realpath "$dso")" "$seq-corrected" "$seq-dso" dso-corrected-every3 1 3 || true
    echo "$seed|DSO, corrected frames, every third|$seq-dso" >> "$index"
    printf . >&2
  fi
done
echo >&2
/usr/bin/python3 "$here/scripts/study/knobs_table.py" "$index" "$out_md" \
  "street/drive, 320x256, 60 Hz, tau $TAU s, noise 3 counts, 3 x 3 rays a pixel, $SECONDS_LONG s, seeds $SEEDS"
echo "precision-knobs: wrote $out_md" >&2
