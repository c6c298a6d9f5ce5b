#!/usr/bin/env bash
# Set-up command: installs dependencies, builds, and runs the main job: the two-frame corrector
# over a real recording from ../shared/data (or a generated one when that folder is absent),
# then PNG views of raw vs corrected in ./out.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
scripts/build.sh

bolo=build/apps/bolo
mkdir -p out
shared=../shared/data/real/lepton3-possum
if [ -f "$shared/frames.npy" ]; then
  rec=$shared
  timing=(--exposure 0.01 --readout 0.1)
else
  echo "bolo: $shared is absent; generating a small recording with ghosting instead" >&2
  rec=out/demo
  "$bolo" simulate "$rec" --overwrite
  timing=()
fi
"$bolo" info "$rec"
"$bolo" correct "$rec" out/corrected --tau-h 0.012 --tau-c 0.012 "${timing[@]}" --overwrite
"$bolo" render "$rec" out/compare.png --frame 40 --compare out/corrected --scale 3
"$bolo" render out/corrected out/contact-sheet.png --contact-sheet
echo "bolo: wrote out/corrected (recording), out/compare.png (raw | corrected), out/contact-sheet.png"
