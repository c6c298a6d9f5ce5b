#!/usr/bin/env bash
# One study run: bolo odometry over SEQ in MODE into RUN (replaced), then bolo evaluate into
# RUN/evaluation.json (and its trajectory-refined.tum into RUN/evaluation-refined.json). Exit 0 when
# the run could be evaluated; otherwise 1 (a run with fewer than 3 poses: the studies count it as a
# failure). bolo odometry's messages go to RUN.err, bolo
# evaluate's to RUN/evaluate.err. Shared by odometry-study.sh, rerun-grid.sh and long-walks.sh.
#
#   scripts/study/run-vo.sh BOLO SEQ MODE RUN [bolo odometry options...]
set -uo pipefail
[ $# -ge 4 ] || { echo "usage: run-vo.sh BOLO SEQ MODE RUN [odometry options...]" >&2; exit 2; }
bolo=$1 seq=$2 mode=$3 run=$4
shift 4
"$bolo" odometry "$seq" --out "$run" --photometric "$mode" --overwrite --no-progress "$@" > /dev/null 2> "$run.err"
"$bolo" evaluate "$run" --json "$run/evaluation.json" > /dev/null 2> "$run/evaluate.err" || exit 1
"$bolo" evaluate "$run" --refined --json "$run/evaluation-refined.json" > /dev/null 2>> "$run/evaluate.err" || true
