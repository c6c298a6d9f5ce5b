#!/bin/sh
# HIL scenario, run inside the VM: the PureThermal emulator (UVC Y16, 160x120 and 160x122 with
# Lepton telemetry rows) on the configfs UVC gadget function (usb_f_uvc bulk build of
# toolchain/vm/uvc-gadget.sh), frames of the lepton3-possum recording (simulated ones without
# ../shared); the host side through the real uvcvideo driver and the project's V4l2Source:
# 1) 160x122 without faults, FFC every 100 frames: none lost, every image and telemetry counter
# bit-exact, every FFC seen; 2) 160x120 (no telemetry rows); 3) 1 % of each of short frame,
# duplicate, silence; 4) unplug/replug (2 % of 300 frames).
# BOLO_HIL_UVC_FRAMES (run-hil-test.sh: 10000 on x86-64) sets the clean run's length; the fault
# run streams a quarter of it.
# device: usb:purethermal
# real: echo "a real PureThermal: use BOLO_HIL_DEVICE=v4l2:/dev/videoN (vivid.sh: bolo capture)"; exit 77
frames="${BOLO_HIL_UVC_FRAMES:-1000}"
fault_frames=$((frames / 4))
recording=""
if [ -d ./lepton3-possum ]; then
  recording="--recording ./lepton3-possum"
else
  echo "uvc: no lepton3-possum recording (../shared/data absent): simulated frames"
fi
failed=0

run() {  # name, emulator arguments, host arguments
  name="$1"
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  # --credit/--progress: the emulator stays at most 8 frames ahead of what the host program has
  # delivered (it has 16 buffers), so uvcvideo always has a buffer: a lost frame is the stack's.
  ./uvc_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" \
    --done "/tmp/$name.done" --finished "/tmp/$name.finished" --credit "/tmp/$name.progress:8" $recording $2 &
  emulator=$!
  ./hil_uvc_hal --send-log "/tmp/$name.log" --done "/tmp/$name.done" --progress "/tmp/$name.progress" \
    --buffers 16 $3 || failed=1
  touch "/tmp/$name.finished"
  wait $emulator || { echo "HIL-STEP $name: the emulator failed"; failed=1; }
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}

run uvc_clean "--frames $frames --ffc-period 100" "--size 160x122 --min-frames $frames --ffc-period 100"
run uvc_plain "--frames 300" "--size 160x120 --min-frames 300"
run uvc_faults "--frames $fault_frames --ffc-period 100 --fault-rate 0.01 --seed 3 \
  --faults short_transfer,duplicate,timeout" "--size 160x122 --min-frames $((fault_frames * 9 / 10)) --ffc-period 100"
run uvc_replug "--frames 300 --fault-rate 0.02 --seed 5 --faults disconnect" \
  "--size 160x122 --min-frames 250 --lost-per-unplug 4"
exit $failed
