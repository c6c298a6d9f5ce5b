#!/usr/bin/env bash
# Fails when a target depends on a higher layer (docs/architecture.md, "Layers"), naming each such
# edge of the target graph that `cmake --graphviz` writes. Layers, lowest first:
#   0  bolo_fixed_point
#   1  bolo_core
#   2  firmware stages (bolo_firmware, bolo_vo) | HAL board parts (bolo_hal, bolo_hal_raw,
#      bolo_hal_faults, bolo_hal_protocols, bolo_recording): neither side depends on the other
#   3  host HAL (bolo_hal_devices, bolo_hal_player, bolo_hal_sources, bolo_hal_sinks)
#   4  sim libraries (bolo_sim, bolo_scene, bolo_effects, bolo_diagnose, bolo_odometry)
#   5  any other target: the CLI, benchmarks, tests, fuzz targets, firmware/examples
# Imported targets (a::b) and library files are outside the project and not checked; a new
# library belongs in the list (until it is, it counts as layer 5 when named bolo*).
#
# Usage: scripts/check-layers.sh [BUILD_DIR]
#   BUILD_DIR  a configured build; default build-layers, configured here if needed (configure only:
#              nothing is compiled).
# Exit code: 0 no upward edge, 1 upward edges (each printed), 2 cmake failed.
set -euo pipefail

cd "$(dirname "$0")/.."
build=${1:-build-layers}
if [ ! -f "$build/CMakeCache.txt" ]; then
  echo "== configuring $build (configure only)"
  cmake -S . -B "$build" -G Ninja >/dev/null || exit 2
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# --graphviz re-runs the configure step of the build directory; the graph goes to $tmp.
cmake --graphviz="$tmp/targets.dot" "$build" >/dev/null || exit 2

awk '
  function layer(t) {
    if (t == "bolo_fixed_point") return 0
    if (t == "bolo_core") return 1
    if (t == "bolo_firmware" || t == "bolo_vo") return 2
    if (t ~ /^bolo_hal(_raw|_faults|_protocols)?$/ || t == "bolo_recording") return 2
    if (t ~ /^bolo_hal_(devices|player|sources|sinks)$/) return 3
    if (t ~ /^bolo_(sim|scene|effects|diagnose|odometry)$/) return 4
    if (t ~ /::|^\/|^-/) return -1  # imported targets, library files, flags: not the project'"'"'s
    return 5
  }
  function side(t) {  # the two halves of layer 2
    if (t == "bolo_firmware" || t == "bolo_vo") return "firmware stages"
    if (layer(t) == 2) return "HAL board parts"
    return ""
  }
  # "node5" [ label = "bolo_recording\n(bolo::recording)", shape = octagon ];
  /^[ \t]*"node[0-9]+" \[ label = "/ {
    id = $1; gsub(/"/, "", id)
    name = $0; sub(/^[^=]*= "/, "", name); sub(/(\\n|").*$/, "", name)
    names[id] = name
    next
  }
  # "node5" -> "node8"  // bolo_recording -> bolo_core
  /^[ \t]*"node[0-9]+" -> "node[0-9]+"/ {
    from = $1; to = $3; gsub(/"/, "", from); gsub(/"/, "", to)
    a = names[from]; b = names[to]
    # A plain name outside the list may be a system library (-lm): a dependee counts when it is
    # one of the layers above or named bolo*.
    if (layer(a) < 0 || layer(b) < 0 || (layer(b) == 5 && b !~ /^bolo/) || seen[a " " b]++) next
    edges++
    if (layer(b) > layer(a))
      printf "check-layers: upward edge %s (layer %d) -> %s (layer %d%s)\n", a, layer(a), b, layer(b),
             layer(b) == 5 ? ", not listed here" : ""
    else if (layer(a) == 2 && layer(b) == 2 && side(a) != side(b))
      printf "check-layers: edge across layer 2: %s (%s) -> %s (%s)\n", a, side(a), b, side(b)
    else
      next
    bad++
  }
  END {
    if (bad) { printf "check-layers: %d edge(s) against the layers\n", bad; exit 1 }
    printf "check-layers: no upward edge (%d edges between the project'"'"'s targets)\n", edges
  }
' "$tmp/targets.dot"
