#!/usr/bin/env bash
# Runs a study's jobs two at a time (JOBS), a dot on stderr per run: each line of JOBS_FILE is
# `SEQ MODE RUN [bolo odometry options...]`, done by run-vo.sh with BOLO. With KEEP_DONE=1 a run
# whose evaluation.json exists is kept. A run that fails is left for the tables to count. Shared
# by pans.sh, frame-rates.sh and coring-strength.sh.
#
#   scripts/study/run-jobs.sh BOLO JOBS_FILE
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: run-jobs.sh BOLO JOBS_FILE" >&2; exit 2; }
export BOLO_BIN="$1" RUN_VO KEEP_DONE="${KEEP_DONE:-0}"
RUN_VO="$(cd "$(dirname "$0")" && pwd)/run-vo.sh"
# shellcheck disable=SC2016
xargs -P "${JOBS:-2}" -L 1 sh -c '
  seq=$0 mode=$1 run=$2
  shift 2
  if [ "$KEEP_DONE" != 1 ] || [ ! -f "$run/evaluation.json" ]; then "$RUN_VO" "$BOLO_BIN" "$seq" "$mode" "$run" "$@" || true; fi
  printf . >&2' < "$2"
echo >&2
