#!/usr/bin/env bash
# Real motion: bolo odometry over ../shared/data/real/optris-pi450-handheld (382x288, ~28 Hz,
# handheld, OpenCV rational lens model in camera.json, strong fixed pattern, no ground truth), on
# the raw frames and on the frames with their fixed pattern taken out (median_nuc.py, then
# `bolo correct --nuc` with the two-frame correction off: tau 0.1 ms), with camera.json and with a
# distortion-free --hfov 53.7 instead, in none and ir-loop. The check without ground truth is the
# sequence run backwards (none): `bolo evaluate FORWARD --truth REVERSED/trajectory.tum`, the
# forward run's ATE (% of the path) and RPE rotation against the reversed run's. Writes the table
# OUT_MD (optris_table.py; default docs/odometry-study/optris-handheld.md). ~1 min.
#
#   scripts/study/optris-handheld.sh BOLO WORK [OUT_MD]
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: optris-handheld.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/optris-handheld.md}
rec=$(realpath -m "${REC:-$here/../shared/data/real/optris-pi450-handheld}")
[ -f "$rec/camera.json" ] || { echo "optris-handheld: $rec is absent (../shared/data)" >&2; exit 2; }
mkdir -p "$work"
python3 "$here/scripts/study/median_nuc.py" "$rec" "$work/nuc.npy"
"$bolo" correct "$rec" "$work/nuc" --nuc "$work/nuc.npy" --tau-h 0.0001 --tau-c 0.0001 \
  --exposure 0.0178 --readout 0.0178 --overwrite > /dev/null
index="$work/index.txt"
: > "$index"
for input in raw nuc; do
  source_dir="$rec"
  [ "$input" = nuc ] && source_dir="$work/nuc"
  for lens in camera.json hfov; do
    lens_args=()
    [ "$lens" = hfov ] && lens_args=(--hfov 53.7)
    for mode in none ir-loop; do
      run="$work/$input-$lens-$mode"
      "$bolo" odometry "$source_dir" --out "$run" --photometric "$mode" "${lens_args[@]}" --overwrite --no-progress > /dev/null
      if [ "$mode" = none ]; then
        "$bolo" odometry "$source_dir" --out "$run-reversed" --photometric "$mode" --reverse "${lens_args[@]}" \
          --overwrite --no-progress > /dev/null
        "$bolo" evaluate "$run" --truth "$run-reversed/trajectory.tum" --rpe-delta 0.25 --json "$run/reversed.json" > /dev/null
      fi
      echo "$input $lens $mode $run" >> "$index"
    done
  done
done
python3 "$here/scripts/study/optris_table.py" "$index" "$out_md" "$rec"
echo "optris-handheld: wrote $out_md"
