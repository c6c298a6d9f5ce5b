#!/bin/sh
# HIL scenario, run inside the VM: vivid (the kernel's virtual V4L2 camera, webcam input, Y16) as
# a second V4L2 source: `bolo capture --device v4l2:/dev/video0` through the project's V4L2
# backend must deliver every frame asked for with increasing timestamps and count what vivid
# dropped. Not bit-exact: vivid's test pattern is not logged. Skipped without the CLI.
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
