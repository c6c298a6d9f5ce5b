#!/usr/bin/env bash
# Regenerates docs/odometry-study.md and its figures: simulated street sequences (bolo simulate),
# the VO in all four photometric modes (bolo odometry), metrics (bolo evaluate), then a table
# and SVG charts (scripts/study/summarise.py, Python 3 standard library only).
#
#   scripts/odometry-study.sh [BUILD_DIR] [WORK_DIR]
#
# Grid (environment overrides): TRAJECTORIES="drive handheld" FPS="30 60" TAUS="0.0002 0.008
# 0.012 0.015" SEEDS="1 2 3" SECONDS_LONG=4 SIZE=160x120 NOISE=3 MODES="none affine ir ir-loop"
# SUPERSAMPLE=1 (rays per pixel per axis, bolo simulate --supersample) DOCS=docs/odometry-study.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
work="${2:-$here/out/odometry-study}"
bolo="$build/apps/bolo"
[ -x "$bolo" ] || { echo "odometry-study: $bolo not built (cmake --build $build --target bolo)" >&2; exit 2; }

TRAJECTORIES="${TRAJECTORIES:-drive handheld}"
FPS="${FPS:-30 60}"
TAUS="${TAUS:-0.0002 0.008 0.012 0.015}"
SEEDS="${SEEDS:-1 2 3}"
SECONDS_LONG="${SECONDS_LONG:-4}"
SIZE="${SIZE:-160x120}"
NOISE="${NOISE:-3}"
MODES="${MODES:-none affine ir ir-loop}"
SUPERSAMPLE="${SUPERSAMPLE:-1}"
DOCS="${DOCS:-$here/docs/odometry-study}"
ss_tag=""
[ "$SUPERSAMPLE" = 1 ] || ss_tag="-ss$SUPERSAMPLE"

mkdir -p "$work"
for traj in $TRAJECTORIES; do
  for fps in $FPS; do
    frames=$(( SECONDS_LONG * fps ))
    for tau in $TAUS; do
      for seed in $SEEDS; do
        seq="$work/seq-$traj-${fps}hz-tau$tau-s$seed$ss_tag"
        if [ ! -d "$seq" ]; then
          "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$fps" --frames "$frames" \
            --size "$SIZE" --tau "$tau" --noise "$NOISE" --seed "$seed" --supersample "$SUPERSAMPLE" > /dev/null
        fi
        for mode in $MODES; do
          run="$seq-vo-$mode"
          # A run too short to evaluate (fewer than 3 poses) counts as a failure in the table.
          if "$here/scripts/study/run-vo.sh" "$bolo" "$seq" "$mode" "$run"; then
            echo "$traj $fps $tau $seed $mode $run/evaluation.json"
          else
            echo "$traj $fps $tau $seed $mode FAILED"
          fi
        done
      done
    done
  done
done > "$work/index$ss_tag.txt"
python3 "$here/scripts/study/summarise.py" "$work/index$ss_tag.txt" "$DOCS" \
  "size $SIZE, noise $NOISE counts, ${SECONDS_LONG} s per sequence, seeds $SEEDS, $SUPERSAMPLE x $SUPERSAMPLE rays per pixel"
# Example trajectories for the page: 60 Hz, tau 12 ms, seed 1, none and ir.
for traj in $TRAJECTORIES; do
  for mode in none ir; do
    svg="$work/seq-$traj-60hz-tau0.012-s1$ss_tag-vo-$mode/trajectory.svg"
    [ -f "$svg" ] && cp "$svg" "$DOCS/trajectory-$traj-60hz-tau12-$mode.svg"
  done
done
echo "odometry-study: wrote $DOCS/results.md and figures from $(wc -l < "$work/index$ss_tag.txt") runs"
