#!/usr/bin/env bash
# DSO beside bolo on the same frames: the study's street sequences (bolo simulate, as
# scripts/odometry-study.sh renders them) per trajectory type and seed, bolo odometry in each mode
# (run-vo.sh) and the DSO peer (dso-run.sh) on the raw frames and on `bolo correct`ed ones (the
# paper's two-frame correction with the rendered tau), each at the full rate and every third
# frame, all scored by bolo evaluate. One run at a time; each run's wall and CPU time are kept
# (both programs run single-threaded here). Writes WORK/index-dso.txt and the table OUT_MD
# (scripts/study/dso_table.py; default docs/odometry-study/dso.md).
#
#   scripts/study/dso-side-by-side.sh BOLO DSO_DATASET WORK [OUT_MD]
#
# DSO_DATASET from scripts/study/dso-build.sh. Environment: TRAJECTORIES (drive handheld), SEEDS
# (1 .. 10), SIZE (320x256), FPS (60), TAU (0.010), NOISE (3), SUPERSAMPLE (3), SECONDS_LONG (4),
# LAG (exposure-readout; continuous: `bolo simulate --lag continuous`), SUBSTEPS (simulate's default),
# MODES (none affine ir ir-loop), DSO_VARIANTS (dso dso-corrected dso-every3 dso-corrected-every3;
# a suffix -everyK gives DSO every K-th frame). Sequences already in WORK are reused; runs are
# redone unless KEEP_DONE=1 (then a finished run is kept, with its times).
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: dso-side-by-side.sh BOLO DSO_DATASET WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); dso=$(realpath "$2"); work=$(realpath -m "$3")
out_md=${4:-$here/docs/odometry-study/dso.md}
TRAJECTORIES="${TRAJECTORIES:-drive handheld}"
SEEDS="${SEEDS:-1 2 3 4 5 6 7 8 9 10}"
SIZE="${SIZE:-320x256}"
FPS="${FPS:-60}"
TAU="${TAU:-0.010}"
NOISE="${NOISE:-3}"
SUPERSAMPLE="${SUPERSAMPLE:-3}"
SECONDS_LONG="${SECONDS_LONG:-4}"
MODES="${MODES:-none affine ir ir-loop}"
DSO_VARIANTS="${DSO_VARIANTS:-dso dso-corrected dso-every3 dso-corrected-every3}"
KEEP_DONE="${KEEP_DONE:-0}"
LAG="${LAG:-exposure-readout}"
SUBSTEPS="${SUBSTEPS:-}"
[ -x "$bolo" ] || { echo "dso-side-by-side: $bolo is not an executable" >&2; exit 2; }
[ -x "$dso" ] || { echo "dso-side-by-side: $dso is not an executable (scripts/study/dso-build.sh)" >&2; exit 2; }
frames=$((SECONDS_LONG * FPS))
# shellcheck source=scripts/study/sequence-name.sh
. "$here/scripts/study/sequence-name.sh"
study_render_options "$LAG" "$SUBSTEPS"
mkdir -p "$work"
index="$work/index-dso.txt"
: > "$index"
TIMEFORMAT='%R %U %S'
for traj in $TRAJECTORIES; do
  for seed in $SEEDS; do
    seq=$(study_sequence "$work" "$traj" "$SIZE" "$FPS" "$TAU" "$SUPERSAMPLE" "$LAG" "$SUBSTEPS" "$seed")
    if [ ! -d "$seq" ]; then
      "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$FPS" --frames "$frames" --size "$SIZE" \
        --tau "$TAU" --noise "$NOISE" --seed "$seed" --supersample "$SUPERSAMPLE" "${study_render[@]}" > /dev/null
    fi
    for mode in $MODES; do
      run="$seq-vo-$mode"
      if [ "$KEEP_DONE" != 1 ] || [ ! -f "$run.times" ]; then
        # Wall and CPU time (user + system) of bolo odometry and bolo evaluate (tens of ms).
        times=$( { time "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run" || true; } 2>&1 )
        read -r wall user sys <<< "$times"
        echo "$wall $(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" > "$run.times"
      fi
      echo "$traj $seed $mode $(cat "$run.times") $run" >> "$index"
      printf . >&2
    done
    for variant in $DSO_VARIANTS; do
      input=$seq first=0 stride=1
      case $variant in
        dso-corrected*)
          input="$seq-corrected"
          [ -d "$input" ] || "$bolo" correct "$seq" "$input" --tau-h "$TAU" --tau-c "$TAU" --no-progress > /dev/null
          first=1 ;;  # bolo correct's first frame has no predecessor: gain only, far brighter
      esac
      case $variant in *-every*) stride=${variant##*-every} ;; esac
      run="$seq-$variant"
      if [ "$KEEP_DONE" != 1 ] || [ ! -f "$run/summary.json" ]; then
        "$here/scripts/study/dso-run.sh" "$bolo" "$dso" "$input" "$run" "$variant" "$first" "$stride" || true
      fi
      echo "$traj $seed $variant - - $run" >> "$index"
      printf . >&2
    done
  done
done
echo >&2
/usr/bin/python3 "$here/scripts/study/dso_table.py" "$index" "$out_md" \
  "street, $SIZE, $FPS Hz, tau $TAU s, noise $NOISE counts, $SUPERSAMPLE x $SUPERSAMPLE rays a pixel, pixel lag $LAG${SUBSTEPS:+, $SUBSTEPS sub-steps}, $SECONDS_LONG s, seeds $SEEDS"
echo "dso-side-by-side: wrote $out_md from $(wc -l < "$index") runs"
