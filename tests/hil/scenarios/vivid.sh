#!/bin/sh
# HIL scenario, run inside the VM: vivid (the kernel's virtual V4L2 camera, webcam input, Y16) as
# a second V4L2 source: `bolo capture --device v4l2:/dev/video0` through the project's V4L2
# backend must deliver every frame asked for with increasing timestamps and count what vivid
# dropped; then the 8-bit modes forced (?format=GREY, ?format=YUYV): marked tone-mapped in the
# recording (units counts8, 8 bits), which `bolo correct` refuses. Not bit-exact: vivid's test
# pattern is not logged. Skipped without the CLI.
# device: v4l2
# real: bolo capture --device "$BOLO_HIL_DEVICE" --out /tmp/hil-v4l2 --frames 300 --no-progress --overwrite
[ -x ./bolo ] || { echo "no bolo CLI in this build" >/tmp/skip-reason; exit 77; }
[ -e /dev/video0 ] || { echo "vivid did not register /dev/video0"; exit 1; }
frames=30
./bolo capture --device v4l2:/dev/video0 --out /tmp/vivid --frames $frames --no-progress || exit 1
cat /tmp/vivid/capture.json
rows=$(($(wc -l </tmp/vivid/frames.csv) - 1))
[ "$rows" -eq $frames ] || { echo "vivid: $rows frames written, want $frames"; exit 1; }
grep -q "\"frames_delivered\": $frames," /tmp/vivid/capture.json || { echo "vivid: frames_delivered"; exit 1; }
grep -q '"timestamps_not_increasing": 0' /tmp/vivid/capture.json || { echo "vivid: timestamps"; exit 1; }
for format in GREY YUYV; do
  out=/tmp/vivid-$format
  ./bolo capture --device "v4l2:/dev/video0?format=$format" --out $out --frames 5 --no-progress || exit 1
  grep -q '"units": "counts8"' $out/recording.json || { echo "vivid $format: not marked counts8"; cat $out/recording.json; exit 1; }
  grep -q '"bits": 8' $out/recording.json || { echo "vivid $format: not 8 bits"; exit 1; }
  if ./bolo correct $out /tmp/vivid-corrected --tau-h 0.012 --tau-c 0.012 --exposure 0.01 --readout 0.02 2>/tmp/vivid-err; then
    echo "vivid $format: bolo correct accepted tone-mapped frames"; exit 1
  fi
  grep -q "units counts8" /tmp/vivid-err || { echo "vivid $format: refusal"; cat /tmp/vivid-err; exit 1; }
  rm -rf $out
done
