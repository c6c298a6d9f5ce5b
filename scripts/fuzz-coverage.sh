#!/usr/bin/env bash
# Source coverage reached by each fuzz target's corpus: builds the corpus replay drivers
# (fuzz_<target>_replay) with clang's source-based coverage into build-fuzz-cov, replays
#   fuzz/corpus/<target>, fuzz/regressions/<target> and, if given, CORPUS_ROOT/<target>
# (e.g. the grown corpora a long fuzz run kept: BOLO_FUZZ_LOGS=DIR scripts/fuzz-smoke.sh 600),
# and prints, per target, the line and branch coverage of every project source file it reached
# (paths relative to the folder those files share, as llvm-cov prints them).
# libFuzzer's own "cov:" figure counts instrumented edges in everything linked, the standard
# library included; this says how much of *our* parsing code the inputs exercise.
#
#   scripts/fuzz-coverage.sh [CORPUS_ROOT]
# Exit code: 0 when every replay ran clean, 1 otherwise, 2 when clang/llvm tools are missing.
set -uo pipefail
cd "$(dirname "$0")/.."
extra=${1:-}
build=build-fuzz-cov

profdata=$(command -v llvm-profdata-14 || command -v llvm-profdata || true)
llvmcov=$(command -v llvm-cov-14 || command -v llvm-cov || true)
if ! command -v clang++ >/dev/null || [ -z "$profdata" ] || [ -z "$llvmcov" ]; then
  echo "fuzz-coverage: needs clang++, llvm-profdata and llvm-cov (apt-get install clang llvm)" >&2
  exit 2
fi

flags="-fprofile-instr-generate -fcoverage-mapping"
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fprofile-instr-generate" -DBOLO_WERROR=OFF >/dev/null || exit 1
mapfile -t replays < <(ninja -C "$build" -t targets all | sed -n 's/^\(fuzz_[a-z_0-9]*_replay\): .*/\1/p' | sort -u)
[ ${#replays[@]} -gt 0 ] || { echo "fuzz-coverage: no replay targets configured" >&2; exit 1; }
cmake --build "$build" -j "$(nproc)" --target "${replays[@]}" >/dev/null || exit 1

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
printf '%-18s %6s %9s %9s  %s\n' target inputs lines branches "files reached (line coverage)"
for replay in "${replays[@]}"; do
  t=${replay#fuzz_}; t=${t%_replay}
  dirs=()
  for d in "fuzz/corpus/$t" "fuzz/regressions/$t" ${extra:+"$extra/$t"}; do
    [ -d "$d" ] && dirs+=("$d")
  done
  inputs=0
  for d in "${dirs[@]}"; do inputs=$((inputs + $(find "$d" -type f ! -name 'README*' | wc -l))); done
  # One profile per input file would be exact but slow; the driver takes whole folders.
  if ! LLVM_PROFILE_FILE="$work/$t.profraw" "$build/fuzz/$replay" "${dirs[@]}" >"$work/$t.log" 2>&1; then
    echo "fuzz-coverage: $t: replay failed (see below)" >&2
    tail -20 "$work/$t.log" >&2
    status=1
    continue
  fi
  "$profdata" merge -sparse "$work/$t.profraw" -o "$work/$t.profdata"
  # Project sources only (not tests, fuzz drivers, or system headers).
  "$llvmcov" report "$build/fuzz/$replay" -instr-profile="$work/$t.profdata" \
    -ignore-filename-regex='(/usr/|/fuzz/|/tests/|/_deps/)' >"$work/$t.report" 2>/dev/null
  # Columns of `llvm-cov report`: Filename Regions Missed Cover Functions Missed Executed
  # Lines Missed Cover Branches Missed Cover. Totals are over the files the target reached (a
  # library linked whole would otherwise count its unrelated files as missed).
  awk -v t="$t" -v n="$inputs" -v root="$PWD/" '
    NF >= 13 && $1 != "TOTAL" && $2 ~ /^[0-9]+$/ && $8 > 0 && $8 != $9 {
      sub(root, "", $1); files = files sprintf(" %s(%s)", $1, $10)
      l += $8; lm += $9; b += $11; bm += $12 }
    END {
      printf "%-18s %6d %8.1f%% %8.1f%% %s\n", t, n, l ? 100 * (l - lm) / l : 0,
             b ? 100 * (b - bm) / b : 0, files }' "$work/$t.report"
done
exit $status
