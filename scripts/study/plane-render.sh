#!/usr/bin/env bash
# A render from outside bolo's simulator (plane-render/plane_render.cpp: a real thermal frame on a
# ground plane, the paper's two-frame ghost, its own code), the VO in every mode and in ir with the
# true tau held, evaluated; writes the table OUT_MD (plane_table.py; default
# docs/odometry-study/plane-render.md). Needs ../shared/data/real/flir-t1030-hand (the texture).
#
#   scripts/study/plane-render.sh BOLO WORK [OUT_MD]
#
# Environment: TAUS="0.008 0.010 0.015" NOISES="0 3" FPS=60 SIZE=320x256 FRAMES=300 JOBS=2.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: plane-render.sh BOLO WORK [OUT_MD]" >&2; exit 2; }
here="$(cd "$(dirname "$0")/../.." && pwd)"
bolo=$(realpath "$1"); work=$(realpath -m "$2")
out_md=${3:-$here/docs/odometry-study/plane-render.md}
texture="$here/../shared/data/real/flir-t1030-hand/frames.npy"
[ -f "$texture" ] || { echo "plane-render: $texture is absent (../shared/data)" >&2; exit 2; }
TAUS="${TAUS:-0.008 0.010 0.015}"
NOISES="${NOISES:-0 3}"
FPS="${FPS:-60}"
SIZE="${SIZE:-320x256}"
FRAMES="${FRAMES:-300}"
mkdir -p "$work"
gen="$work/plane_render"
c++ -O2 -std=c++20 -Wall -Wextra -I/usr/include/eigen3 "$here/scripts/study/plane-render/plane_render.cpp" -o "$gen"
jobs="$work/jobs.txt"
: > "$jobs"
index="$work/index.txt"
: > "$index"
for tau in $TAUS; do
  for noise in $NOISES; do
    seq="$work/plane-${FPS}hz-tau$tau-noise$noise"
    [ -d "$seq" ] || "$gen" "$texture" "$seq" "${SIZE%x*}" "${SIZE#*x}" "$FRAMES" "$FPS" "$tau" "$noise"
    for mode in none affine ir ir-loop; do
      echo "$seq $mode $seq-vo-$mode" >> "$jobs"
      echo "$tau $noise $mode $seq-vo-$mode" >> "$index"
    done
    echo "$seq ir $seq-vo-ir-true --fixed-tau --tau-init $tau" >> "$jobs"
    echo "$tau $noise ir-true $seq-vo-ir-true" >> "$index"
  done
done
"$here/scripts/study/run-jobs.sh" "$bolo" "$jobs"
python3 "$here/scripts/study/plane_table.py" "$index" "$out_md" \
  "plane_render: FLIR T1030 frame on a plane, $SIZE, $FPS Hz, $FRAMES frames, 0.3 m/s at ~1.2 m"
echo "plane-render: wrote $out_md from $(wc -l < "$index") runs"
