#!/usr/bin/env bash
# Fuzz smoke test for CI: builds the libFuzzer targets of the `asan` preset (clang, ASan + UBSan,
# coverage-instrumented libraries; the same build the sanitizer stage tests, so CI compiles the
# instrumented code once) and runs every fuzz target for a short fixed time, starting from its committed corpus and regressions
# (fuzz/corpus/<target>, fuzz/regressions/<target>; new inputs go to a scratch folder). Fails on
# any crash, leak, timeout or broken property; the input that did it is kept in
# build-asan/artifacts/<target>/ and printed (base64) with the report.
#   scripts/fuzz-smoke.sh [SECONDS]      (per target; default 5, or $BOLO_FUZZ_SECONDS)
set -uo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${BOLO_FUZZ_SECONDS:-5}}
jobs=$(nproc)

cmake --preset asan >/dev/null || exit 1
cmake --build --preset fuzzers -j "$jobs" || exit 1

work=$(mktemp -d)
# BOLO_FUZZ_LOGS=DIR keeps each target's libFuzzer log and its grown corpus (long runs).
trap '[ -n "${BOLO_FUZZ_LOGS:-}" ] && mkdir -p "$BOLO_FUZZ_LOGS" && cp -r "$work"/. "$BOLO_FUZZ_LOGS"/; rm -rf "$work"' EXIT
targets=()
# BOLO_FUZZ_TARGETS="a b" runs only those targets.
for bin in build-asan/fuzz/fuzz_*; do
  t=${bin##*/fuzz_}
  [ -x "$bin" ] || continue
  [[ $t == *_replay ]] && continue  # the corpus replays of the test suite, not libFuzzer binaries
  [ -z "${BOLO_FUZZ_TARGETS:-}" ] || [[ " $BOLO_FUZZ_TARGETS " == *" $t "* ]] && targets+=("$t")
done
[ ${#targets[@]} -gt 0 ] || { echo "fuzz-smoke: no fuzz targets built" >&2; exit 1; }

run_one() {  # target -> exit status of libFuzzer; log in $work/<target>.log
  local t=$1 dirs=("$work/$t") d
  for d in fuzz/corpus/$t fuzz/regressions/$t; do [ -d "$d" ] && dirs+=("$d"); done
  mkdir -p "$work/$t" "build-asan/artifacts/$t"
  "build-asan/fuzz/fuzz_$t" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="build-asan/artifacts/$t/" "${dirs[@]}" \
    >"$work/$t.log" 2>&1
}

echo "== fuzz smoke: ${#targets[@]} targets, ${seconds} s each, $jobs at a time"
status=0
for ((i = 0; i < ${#targets[@]}; i += jobs)); do
  batch=("${targets[@]:i:jobs}")
  pids=()
  for t in "${batch[@]}"; do run_one "$t" & pids+=($!); done
  for k in "${!batch[@]}"; do
    t=${batch[$k]}
    if wait "${pids[$k]}"; then
      done_line=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$work/$t.log" | tail -1)
      printf 'fuzz-smoke: %-17s ok   %s\n' "$t" "$(sed -E 's/^#([0-9]+)[[:space:]]+DONE[[:space:]]+/\1 runs, /; s/ corp:.*//' <<<"$done_line")"
    else
      status=1
      printf 'fuzz-smoke: %-17s FAILED\n' "$t" >&2
      grep -E -A40 'ERROR:|runtime error|fuzz property failed|terminate called|Base64' "$work/$t.log" | head -80 >&2
    fi
  done
done
[ $status -eq 0 ] && echo "fuzz-smoke: no crash" || echo "fuzz-smoke: crashes found (inputs in build-asan/artifacts/)" >&2
exit $status
