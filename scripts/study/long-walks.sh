#!/usr/bin/env bash
# Regenerates the odometry study's "Long handheld walks" table: 12-s street walks and drives
# (bolo simulate, 3x3 rays per pixel), the VO in all four photometric modes, evaluated per
# tracking segment, written to docs/odometry-study/long-walks.md by segments_table.py.
#
#   scripts/study/long-walks.sh [BUILD_DIR] [WORK_DIR]
#
# Environment overrides: SEEDS="1 2 3 4" FRAMES=720 (at 60 Hz) TAU=0.010 NOISE=3 SIZE=160x120
# MODES="none affine ir ir-loop" OUT_MD=docs/odometry-study/long-walks.md JOBS=2.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$here/build}"
work="${2:-$here/out/long-walks}"
bolo="$(realpath "$build/apps/bolo" 2>/dev/null || true)"
[ -x "$bolo" ] || { echo "long-walks: $build/apps/bolo not built (cmake --build $build --target bolo)" >&2; exit 2; }
SEEDS="${SEEDS:-1 2 3 4}"
FRAMES="${FRAMES:-720}"
TAU="${TAU:-0.010}"
NOISE="${NOISE:-3}"
SIZE="${SIZE:-160x120}"
MODES="${MODES:-none affine ir ir-loop}"
OUT_MD="${OUT_MD:-$here/docs/odometry-study/long-walks.md}"
mkdir -p "$work"

jobs_file="$work/jobs.txt"
: > "$jobs_file"
for traj in handheld drive; do
  for seed in $SEEDS; do
    seq="$work/long-$traj-s$seed"
    if [ ! -d "$seq" ]; then
      echo "long-walks: rendering $traj seed $seed ($FRAMES frames)" >&2
      "$bolo" simulate "$seq" --scene street --trajectory "$traj" --fps 60 --frames "$FRAMES" \
        --size "$SIZE" --tau "$TAU" --noise "$NOISE" --seed "$seed" --supersample 3 > /dev/null
    fi
    for mode in $MODES; do echo "$traj $seed $mode $seq" >> "$jobs_file"; done
  done
done

run_one() {
  local traj=$1 seed=$2 mode=$3 seq=$4
  if "$RUN_VO" "$BOLO" "$seq" "$mode" "$seq-vo-$mode"; then
    echo "$traj $seed $mode $seq-vo-$mode/evaluation.json"
  else
    echo "$traj $seed $mode FAILED"
  fi
  echo "long-walks: $traj seed $seed $mode done" >&2
}
export -f run_one
export BOLO="$bolo" RUN_VO="$here/scripts/study/run-vo.sh"
xargs -P "${JOBS:-2}" -L 1 bash -c 'run_one "$@"' _ < "$jobs_file" | sort > "$work/index.txt"
python3 "$here/scripts/study/segments_table.py" "$work/index.txt" "$OUT_MD" \
  "street, 60 Hz, $FRAMES frames, $SIZE, tau $TAU s, noise $NOISE counts, 3 x 3 rays per pixel, seeds $SEEDS"
echo "long-walks: wrote $OUT_MD from $(wc -l < "$work/index.txt") runs"
