#!/usr/bin/env bash
# Stripped sizes of the firmware library and of the minimal board program (correct_stream) for
# each target built (build/, build-aarch64/, build-armhf/).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-8s %-28s %12s %12s\n' target file bytes stripped
for entry in "x86-64:build:strip" "aarch64:build-aarch64:aarch64-linux-gnu-strip" "armhf:build-armhf:arm-linux-gnueabihf-strip"; do
  IFS=: read -r name dir strip <<<"$entry"
  for file in "$dir/firmware/libbolo_firmware.a" "$dir/firmware/examples/correct_stream"; do
    [ -f "$file" ] || continue
    cp "$file" "$tmp/f"
    "$strip" --strip-unneeded "$tmp/f"
    printf '%-8s %-28s %12d %12d\n' "$name" "${file#"$dir"/}" "$(stat -c %s "$file")" "$(stat -c %s "$tmp/f")"
  done
done
