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
# SECONDS_LONG (10), TAU (0.010), IR_MODE (the IR mode the settings are changed on: ir or ir-loop;
# default ir), KNOBS (the variants to run, by their numbers in the list below counted from 0;
# default all), TRAJECTORY (drive; handheld), SIZE (320x256), SUPERSAMPLE (3), LAG
# (exposure-readout; continuous), SUBSTEPS (simulate's default). Sequences already in WORK are
# reused, named as dso-side-by-side.sh names them (36-s drives run through the right turn).
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: precision-knobs.sh BOLO DSO_DATASET WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); dso=$2; work=$(realpath -m "$3")
out_md=${4:-$here/docs/odometry-study/precision-knobs.md}
SEEDS="${SEEDS:-1 2 3 4 5}"
SECONDS_LONG="${SECONDS_LONG:-10}"
TAU="${TAU:-0.010}"
TRAJECTORY="${TRAJECTORY:-drive}"
SIZE="${SIZE:-320x256}"
SUPERSAMPLE="${SUPERSAMPLE:-3}"
LAG="${LAG:-exposure-readout}"
SUBSTEPS="${SUBSTEPS:-}"
# shellcheck source=scripts/study/sequence-name.sh
. "$here/scripts/study/sequence-name.sh"
study_render_options "$LAG" "$SUBSTEPS"
tau_low=$(awk -v t="$TAU" 'BEGIN { printf "%.6f", 0.92 * t }')
tau_high=$(awk -v t="$TAU" 'BEGIN { printf "%.6f", 1.08 * t }')
# NAME|MODE|bolo odometry options (one setting changed from the defaults each).
IR_MODE="${IR_MODE:-ir}"
ir=$IR_MODE
variants=(
  "$ir|$ir|"
  "none|none|"
  "$ir, tau held at the truth|$ir|--fixed-tau --tau-init $TAU"
  "$ir, tau held 8 % low|$ir|--fixed-tau --tau-init $tau_low"
  "$ir, tau held 8 % high|$ir|--fixed-tau --tau-init $tau_high"
  "$ir, marginalisation prior|$ir|--marginalisation-prior"
  "$ir, 6 keyframes|$ir|--max-keyframes 6"
  "$ir, no low-pass|$ir|--smoothing 0"
  "$ir, two low-pass passes|$ir|--smoothing 2"
  "$ir, full carry-over correction|$ir|--carry-coring 0"
  "$ir, 1 000 points a keyframe|$ir|--points-per-keyframe 1000"
  "$ir, 1 000 points, tau held at the truth|$ir|--points-per-keyframe 1000 --fixed-tau --tau-init $TAU"
  "none, 1 000 points a keyframe|none|--points-per-keyframe 1000"
  "$ir, marginalisation prior, tau held at the truth|$ir|--marginalisation-prior --fixed-tau --tau-init $TAU"
  "$ir, 1 000 points, marginalisation prior|$ir|--points-per-keyframe 1000 --marginalisation-prior"
  "$ir, keyframe parallax quantile|$ir|--keyframe-parallax quantile"
  "none, keyframe parallax quantile|none|--keyframe-parallax quantile"
  "$ir, keyframe parallax quantile, tau held at the truth|$ir|--keyframe-parallax quantile --fixed-tau --tau-init $TAU"
  "$ir, keyframe parallax quantile, marginalisation prior|$ir|--keyframe-parallax quantile --marginalisation-prior"
  "none, keyframe parallax quantile, marginalisation prior|none|--keyframe-parallax quantile --marginalisation-prior"
)
KNOBS="${KNOBS:-${!variants[*]}}"
mkdir -p "$work"
index="$work/index-knobs.txt"
: > "$index"
for seed in $SEEDS; do
  seq=$(study_sequence "$work" "$TRAJECTORY" "$SIZE" 60 "$TAU" "$SUPERSAMPLE" "$LAG" "$SUBSTEPS" "$seed")
  [ -d "$seq" ] || "$bolo" simulate "$seq" --scene street --trajectory "$TRAJECTORY" --fps 60 \
    --frames $(( SECONDS_LONG * 60 )) --size "$SIZE" --tau "$TAU" --noise 3 --seed "$seed" \
    --supersample "$SUPERSAMPLE" "${study_render[@]}" > /dev/null
  for i in $KNOBS; do
    IFS='|' read -r name mode options <<< "${variants[$i]}"
    run="$seq-knob$i${IR_MODE#ir}"
    # shellcheck disable=SC2086
    "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run" $options || true
    echo "$seed|$name|$run" >> "$index"
    printf . >&2
  done
  if [ "$dso" != - ]; then
    [ -d "$seq-corrected" ] || "$bolo" correct "$seq" "$seq-corrected" --tau-h "$TAU" --tau-c "$TAU" --no-progress > /dev/null
    # The run dso-side-by-side.sh makes of the same frames (reused when it is there).
    dso_run="$seq-dso-corrected-every3"
    [ -f "$dso_run/summary.json" ] ||
      "$here/scripts/study/dso-run.sh" "$bolo" "$(realpath "$dso")" "$seq-corrected" "$dso_run" dso-corrected-every3 1 3 || true
    echo "$seed|DSO, corrected frames, every third|$dso_run" >> "$index"
    printf . >&2
  fi
done
echo >&2
/usr/bin/python3 "$here/scripts/study/knobs_table.py" "$index" "$out_md" \
  "street/$TRAJECTORY, $SIZE, 60 Hz, tau $TAU s, noise 3 counts, $SUPERSAMPLE x $SUPERSAMPLE rays a pixel, pixel lag $LAG${SUBSTEPS:+, $SUBSTEPS sub-steps}, $SECONDS_LONG s, seeds $SEEDS"
echo "precision-knobs: wrote $out_md" >&2
