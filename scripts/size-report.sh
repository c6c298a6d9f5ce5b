#!/usr/bin/env bash
# Stripped sizes of the firmware library and of the minimal board program (correct_stream) for
# each target built (build/, build-aarch64/, build-armhf/), with the shared libraries the program
# needs on the board (libstdc++ and libgcc are linked into it statically).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-8s %-28s %12s %12s  %s\n' target file bytes stripped needs
for entry in "x86-64:build:" "aarch64:build-aarch64:aarch64-linux-gnu-" "armhf:build-armhf:arm-linux-gnueabihf-"; do
  IFS=: read -r name dir prefix <<<"$entry"
  for file in "$dir/firmware/libbolo_firmware.a" "$dir/firmware/examples/correct_stream"; do
    [ -f "$file" ] || continue
    cp "$file" "$tmp/f"
    "${prefix}strip" --strip-unneeded "$tmp/f"
    needs=
    case $file in
      *.a) ;;
      *) needs=$("${prefix}readelf" -d "$file" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | paste -sd, -) ;;
    esac
    printf '%-8s %-28s %12d %12d  %s\n' "$name" "${file#"$dir"/}" "$(stat -c %s "$file")" "$(stat -c %s "$tmp/f")" "$needs"
  done
done
