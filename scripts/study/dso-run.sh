#!/usr/bin/env bash
# One DSO peer run, scored as run-vo.sh scores bolo: SEQ (a bolo recording) as DSO's input
# (scripts/study/dso_io.py: 8-bit PNGs with one linear map for the sequence, times.txt, pinhole
# camera.txt), dso_dataset on it single-threaded without photometric calibration (mode=1 nomt=1),
# its result.txt as a `bolo odometry` output folder in RUN (replaced), then bolo evaluate into
# RUN/evaluation.json. DSO's own log (RUN/dso.log) is kept but never read for the score: it reports
# tracking through scale collapses; the ATE does not. The wall and CPU time of dso_dataset (image
# reading included) go to RUN/summary.json. Exit 0 when the run could be evaluated, else 1.
#
#   scripts/study/dso-run.sh BOLO DSO_DATASET SEQ RUN [NAME [FIRST [STRIDE]]]
#
# NAME labels the run (summary.json's photometric; default dso). DSO is given frames FIRST,
# FIRST + STRIDE, ... (default 0 and 1: all), and the run is scored on those. DSO_TIMEOUT (600 s)
# bounds a run.
# KEEP_INPUT=1 keeps RUN/dso-input (the PNGs). Built by scripts/study/dso-build.sh.
set -uo pipefail
if [ $# -lt 4 ] || [ $# -gt 7 ]; then
  echo "usage: dso-run.sh BOLO DSO_DATASET SEQ RUN [NAME [FIRST [STRIDE]]]" >&2
  exit 2
fi
bolo=$1 dso=$2 seq=$(realpath "$3") run=$(realpath -m "$4") name=${5:-dso} first=${6:-0} stride=${7:-1}
here="$(cd "$(dirname "$0")" && pwd)"
python=/usr/bin/python3  # Debian's, with python3-numpy (a pyenv python first on PATH may lack it)
[ -x "$dso" ] || { echo "dso-run: $dso: not an executable (scripts/study/dso-build.sh builds it)" >&2; exit 2; }
rm -rf "$run"
mkdir -p "$run/dso"
"$python" "$here/dso_io.py" input "$seq" "$run/dso-input" --first "$first" --stride "$stride" || exit 1
frames=$(wc -l < "$run/dso-input/times.txt")
# DSO writes result.txt into its working directory.
# The time goes to the last line of dso.time, after the shell's word of a crash, if any.
TIMEFORMAT='%R %U %S'
{ time (cd "$run/dso" && timeout "${DSO_TIMEOUT:-600}" "$dso" files="$run/dso-input/images" \
  calib="$run/dso-input/camera.txt" mode=1 preset=0 nogui=1 quiet=1 nomt=1 nolog=1 allposes=1 \
  > "$run/dso.log" 2>&1); } 2> "$run/dso.time"
status=$?
read -r wall user sys < <(tail -n 1 "$run/dso.time")
# A crash or a timeout leaves no result.txt (DSO writes it at the end): no poses.
[ -f "$run/dso/result.txt" ] || : > "$run/dso/result.txt"
"$python" "$here/dso_io.py" output "$seq" "$run/dso/result.txt" "$run" --given "$run/dso-input/map.json" \
  --name "$name" --exit-status "$status" --wall-s "$wall" \
  --cpu-s "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" --log "$run/dso.log" || exit 1
[ "${KEEP_INPUT:-0}" = 1 ] || rm -rf "$run/dso-input"
echo "dso-run: $name on $seq: $(wc -l < "$run/trajectory.tum") of $frames frames posed, ${wall} s, dso_dataset exit status $status" > "$run.err"
"$bolo" evaluate "$run" --json "$run/evaluation.json" > /dev/null 2> "$run/evaluate.err"
