#!/usr/bin/env bash
# The IR modes across changes of exposure: street sequences whose exposure switches between half
# the frame period and ALTERNATE of it every EVERY frames (bolo simulate --alternate-exposure,
# the readout taking up the difference), through bolo odometry in every mode, tau started at the
# VO's default (10 ms). Writes WORK/index-switching.txt and the table OUT_MD
# (scripts/study/switching_table.py; default docs/odometry-study/exposure-switching.md).
#
#   scripts/study/exposure-switching.sh BOLO WORK [OUT_MD]
#
# Environment: TRAJECTORIES (drive handheld), TAUS (0.012 0.015), SEEDS (1 2 3), MODES, FPS (60),
# SECONDS_LONG (4), SIZE (160x120), NOISE (3), SUPERSAMPLE (3), ALTERNATE (0.35), EVERY (30),
# SIM_BOLO (the bolo that renders the sequences; default BOLO), OFFSET (0; counts of camera offset
# added to every raw frame by add_offset.py, the runs then in switch-...-offN). Sequences already
# in WORK are reused. Two runs at a time.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: exposure-switching.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$2
out_md=${3:-$here/docs/odometry-study/exposure-switching.md}
sim_bolo=$(realpath "${SIM_BOLO:-$bolo}")
TRAJECTORIES="${TRAJECTORIES:-drive handheld}"
TAUS="${TAUS:-0.012 0.015}"
SEEDS="${SEEDS:-1 2 3}"
MODES="${MODES:-none affine ir ir-loop}"
FPS="${FPS:-60}"
SECONDS_LONG="${SECONDS_LONG:-4}"
SIZE="${SIZE:-160x120}"
NOISE="${NOISE:-3}"
SUPERSAMPLE="${SUPERSAMPLE:-3}"
ALTERNATE="${ALTERNATE:-0.35}"
EVERY="${EVERY:-30}"
OFFSET="${OFFSET:-0}"
mkdir -p "$work"
frames=$(( SECONDS_LONG * FPS ))
exposure=$(python3 -c "print(0.5 / $FPS)")
alternate=$(python3 -c "print($ALTERNATE / $FPS)")
jobs=()
for traj in $TRAJECTORIES; do
  for tau in $TAUS; do
    for seed in $SEEDS; do
      seq="$work/switch-$traj-${FPS}hz-tau$tau-s$seed"
      if [ ! -d "$seq" ]; then
        "$sim_bolo" simulate "$seq" --scene street --trajectory "$traj" --fps "$FPS" --frames "$frames" \
          --size "$SIZE" --tau "$tau" --noise "$NOISE" --seed "$seed" --supersample "$SUPERSAMPLE" \
          --exposure "$exposure" --alternate-exposure "$alternate" --alternate-every "$EVERY" > /dev/null 2>&1
      fi
      if [ "$OFFSET" != 0 ]; then
        [ -d "$seq-off$OFFSET" ] || python3 "$here/scripts/study/add_offset.py" "$seq" "$seq-off$OFFSET" "$OFFSET"
        seq="$seq-off$OFFSET"
      fi
      for mode in $MODES; do jobs+=("$traj $FPS $tau $seed $mode $seq"); done
    done
  done
done
run_one() {
  local traj=$1 fps=$2 tau=$3 seed=$4 mode=$5 seq=$6
  if "$HERE/scripts/study/run-vo.sh" "$BOLO" "$seq" "$mode" "$seq-vo-$mode"; then
    echo "$traj $fps $tau $seed $mode $seq-vo-$mode/evaluation.json"
  else
    echo "$traj $fps $tau $seed $mode FAILED"
  fi
}
export -f run_one
export HERE="$here" BOLO="$bolo"
index="$work/index-switching.txt"
offset_note=""
if [ "$OFFSET" != 0 ]; then
  index="$work/index-switching-off$OFFSET.txt"
  offset_note=", a camera offset of $OFFSET counts"
fi
printf '%s\n' "${jobs[@]}" | xargs -P 2 -L 1 bash -c 'run_one "$@"' _ | sort > "$index"
python3 "$here/scripts/study/switching_table.py" "$index" \
  "street, ${SIZE}, ${FPS} Hz, ${SECONDS_LONG} s, noise ${NOISE} counts, ${SUPERSAMPLE}x${SUPERSAMPLE} rays per pixel, exposure 0.5 / ${ALTERNATE} of the period every ${EVERY} frames${offset_note}, seeds ${SEEDS}" \
  > "$out_md"
echo "exposure-switching: $(wc -l < "$index") runs; table in $out_md"
