#!/usr/bin/env bash
# Reruns the VO over the sequences of a study index (scripts/odometry-study.sh's index*.txt:
# trajectory, Hz, tau, seed, mode, evaluation.json path) into a new folder, leaving the original
# runs alone, and writes OUT/index.txt in the same format for scripts/study/compare_grid.py.
#
#   scripts/study/rerun-grid.sh BOLO INDEX OUT [bolo odometry options...]
#   e.g. scripts/study/rerun-grid.sh build/apps/bolo out/odometry-study/index-ss3.txt /tmp/grid-new
#
# Two runs at a time (JOBS=N to change). The sequence of a run is its folder without "-vo-MODE".
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: rerun-grid.sh BOLO INDEX OUT [odometry options...]" >&2; exit 2; }
bolo=$(realpath "$1"); index=$2; out=$3; shift 3
if [ ! -x "$bolo" ] || [ ! -f "$index" ]; then echo "rerun-grid: $bolo or $index missing" >&2; exit 2; fi
mkdir -p "$out"
run_one() {
  local traj=$1 fps=$2 tau=$3 seed=$4 mode=$5 path=$6
  local seq name run
  seq=$(dirname "$path"); seq=${seq%-vo-"$mode"}
  name=$(basename "$seq")-vo-$mode
  run="$OUT/$name"
  # shellcheck disable=SC2086  # the extra options are meant to split
  if "$RUN_VO" "$BOLO" "$seq" "$mode" "$run" $EXTRA; then
    echo "$traj $fps $tau $seed $mode $run/evaluation.json"
  else
    echo "$traj $fps $tau $seed $mode FAILED"
  fi
}
export -f run_one
here="$(cd "$(dirname "$0")" && pwd)"
export BOLO="$bolo" OUT="$out" EXTRA="$*" RUN_VO="$here/run-vo.sh"
xargs -P "${JOBS:-2}" -L 1 bash -c 'run_one "$@"' _ < "$index" | sort > "$out/index.txt"
echo "rerun-grid: $(wc -l < "$out/index.txt") runs in $out/index.txt"
