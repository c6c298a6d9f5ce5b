#!/usr/bin/env bash
# Static analysis of the code that runs on the camera board: firmware/ (with the VO core,
# firmware/vo), fixed_point/, hal/.
#   1. clang-tidy with the checks of .clang-tidy (every finding is an error) on those folders'
#      sources, using the compile commands of a configured unity build: each unity translation
#      unit includes several of the folders' .cpp files, so the system and Eigen headers are
#      parsed and matched once per unit instead of once per file; the .cpp files and the headers
#      are checked through them (HeaderFilterRegex).
#   2. cppcheck --enable=warning,performance,portability on the same folders.
#   3. scripts/check-layers.sh on the same build: no target depends on a higher layer.
#
# Usage: scripts/static-analysis.sh [BUILD_DIR]
#   BUILD_DIR  a configured build with compile_commands.json; default build-static, configured
#              here if needed (configure only, unity build: nothing is compiled).
#   JOBS=N     parallel clang-tidy / cppcheck processes (default 2: the machine is shared).
#   CLANG_TIDY=path, CPPCHECK=path to pick the tools (default clang-tidy-14 or clang-tidy, cppcheck).
# Exit code: 0 clean, 1 findings, 2 a tool or the build is missing, or clang-tidy killed twice on a
# unit. Prints the run time.
set -euo pipefail

cd "$(dirname "$0")/.."
root=$PWD
build=${1:-build-static}
jobs=${JOBS:-2}
start=$(date +%s)

tidy=${CLANG_TIDY:-$(command -v clang-tidy-14 || command -v clang-tidy || true)}
cppcheck=${CPPCHECK:-$(command -v cppcheck || true)}
if [ -z "$tidy" ] || [ -z "$cppcheck" ]; then
  echo "static-analysis: clang-tidy and cppcheck are needed (apt-get install clang-tidy cppcheck)" >&2
  exit 2
fi

if [ ! -f "$build/compile_commands.json" ]; then
  echo "== configuring $build (compile commands only)"
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_EXPORT_COMPILE_COMMANDS=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
fi
build=$(cd "$build" && pwd)

# The board code's translation units, as the compile database names them: its .cpp files, or the
# unity units whose every included .cpp file is board code.
board_source="^$root/(firmware/(src|examples|vo/src|core/src)|fixed_point|hal/src)/[^/]+\.cpp$"
sources=()
files=0
while read -r file; do
  if [[ $file == */Unity/unity_*.cxx ]]; then
    mapfile -t included < <(sed -n 's/^#include "\(.*\)"$/\1/p' "$file")
    [ ${#included[@]} -gt 0 ] || continue
    printf '%s\n' "${included[@]}" | grep -qvE "$board_source" && continue
    files=$((files + ${#included[@]}))
    sources+=("$file")
  elif grep -qE "$board_source" <<<"$file"; then
    files=$((files + 1))
    sources+=("$file")
  fi
done < <(grep -o '"file": *"[^"]*"' "$build/compile_commands.json" | sed 's/^"file": *"//; s/"$//' | sort -u)
if [ "${#sources[@]}" -eq 0 ]; then
  echo "static-analysis: no firmware/, fixed_point/ or hal/ sources in $build/compile_commands.json" >&2
  exit 2
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0

echo "== clang-tidy ($("$tidy" --version | grep -o 'version [0-9.]*'), $files files in ${#sources[@]} translation units, $jobs jobs)"
# A unity unit is a list of #include "x.cpp" lines by design: that one check is off for it.
# A unit whose clang-tidy was killed (a signal: out of memory beside the VM) is run once more on
# its own after the others; a second kill is reported as a tool failure, not as findings.
tidy_unit() {  # tidy build unit tmp: appends the unit to tmp/failed (findings) or tmp/killed
  sh -c '
    log="$3/$(printf %s "$2" | tr / _).log"
    case "$2" in */Unity/unity_*.cxx) unity=--checks=-bugprone-suspicious-include ;; *) unity= ;; esac
    "$0" -p "$1" --quiet $unity "$2" >"$log" 2>&1
    code=$?
    if [ "$code" -gt 128 ]; then printf "%s\n" "$2" >>"$3/killed"; elif [ "$code" -ne 0 ]; then printf "%s\n" "$2" >>"$3/failed"; fi
  ' "$@"
}
export -f tidy_unit
printf '%s\n' "${sources[@]}" | xargs -P "$jobs" -I{} bash -c 'tidy_unit "$@"' _ "$tidy" "$build" {} "$tmp"
if [ -s "$tmp/killed" ]; then
  mv "$tmp/killed" "$tmp/killed-once"
  while read -r file; do
    echo "clang-tidy was killed on $file (signal); running it again alone"
    tidy_unit "$tidy" "$build" "$file" "$tmp"
  done <"$tmp/killed-once"
fi
if [ -s "$tmp/killed" ]; then
  status=2
  echo "static-analysis: clang-tidy was killed twice on: $(tr '\n' ' ' <"$tmp/killed")(a tool failure, not findings)" >&2
fi
if [ -s "$tmp/failed" ]; then
  status=1
  while read -r file; do
    # The diagnostics, without clang-tidy's "N warnings generated" chatter.
    grep -v -E '^[0-9]+ warnings? (and [0-9]+ errors? )?generated\.$|^Suppressed [0-9]+ warnings|^Use -header-filter|^Error while processing' \
      "$tmp/$(printf %s "$file" | tr / _).log" || true
  done <"$tmp/failed"
  echo "clang-tidy: findings in $(wc -l <"$tmp/failed") of ${#sources[@]} translation units"
elif [ -s "$tmp/killed" ]; then
  echo "clang-tidy: no findings in the units it finished"
else
  echo "clang-tidy: clean"
fi

echo "== cppcheck ($("$cppcheck" --version))"
# Suppressions, each a false positive of cppcheck 2.10 in code owned elsewhere:
#  - CastIntegerToAddressAtReturn in bad_pixel_stage.hpp: `data() + std::size_t{row % 3} * w`
#    is pointer arithmetic; cppcheck misparses the braced std::size_t{...} as the whole value.
#  - uninitvar in two_frame_corrector.cpp (learned_period_ns): `sorted[n / 2]` is read only with
#    n >= 1 (interval_count_ > 0), after the loop filled sorted[0..n-1]; cppcheck assumes the
#    loop may not run. (Reported; `std::int64_t sorted[kIntervalHistory] = {};` would let this
#    suppression go.)
if ! "$cppcheck" --enable=warning,performance,portability --error-exitcode=1 --inline-suppr \
  --std=c++20 --language=c++ --quiet -j "$jobs" \
  -I firmware/core/include -I firmware/include -I firmware/vo/include -I fixed_point/include -I hal/include -I hal/recording/include \
  --suppress=missingIncludeSystem \
  --suppress=CastIntegerToAddressAtReturn:firmware/include/bolo/firmware/bad_pixel_stage.hpp \
  --suppress=uninitvar:firmware/src/two_frame_corrector.cpp \
  firmware/core/src firmware/src firmware/examples firmware/vo/src fixed_point hal/src; then
  status=1
  echo "cppcheck: findings"
else
  echo "cppcheck: clean"
fi

echo "== layers"
scripts/check-layers.sh "$build" || status=1

echo "== static analysis $([ "$status" -eq 0 ] && echo clean || echo FAILED) in $(($(date +%s) - start)) s"
exit "$status"
