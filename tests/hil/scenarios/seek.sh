#!/bin/sh
# HIL scenario, run inside the VM: the Seek Compact emulator on FunctionFS, the host side
# through the project's SeekSource: 1) images without faults, shutter cycles every 100 images:
# none lost, every image bit-exact, every shutter frame an FFC event, the start-up frame's 5
# dead pixels found; 2) 1 % of each fault kind, stalls and unplug/replug included; 3) ~9
# unplug/replug cycles in a row.
# BOLO_HIL_SEEK_FRAMES (run-hil-test.sh: 10000 on x86-64, 1000 in the arm64 VM) sets the clean
# run's length; the fault run streams a quarter of it.
# device: usb:seek
# real: echo "usb:seek on a real camera: not written yet (docs/hil.md)"; exit 77
frames="${BOLO_HIL_SEEK_FRAMES:-1000}"
fault_frames=$((frames / 4))
failed=0

run() {  # name, emulator arguments, host arguments
  name="$1"
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  ./seek_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" \
    --done "/tmp/$name.done" --finished "/tmp/$name.finished" $2 &
  emulator=$!
  ./hil_seek_hal --send-log "/tmp/$name.log" --done "/tmp/$name.done" $3 || failed=1
  touch "/tmp/$name.finished"
  wait $emulator || { echo "HIL-STEP $name: the emulator failed"; failed=1; }
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}

run seek_clean "--frames $frames --shutter-period 100" \
  "--min-frames $frames --shutters $(((frames - 1) / 100)) --dead-pixels 5"
run seek_faults "--frames $fault_frames --shutter-period 100 --fault-rate 0.01 --seed 3 \
  --faults short_transfer,timeout,frame_id_jump,duplicate,stall,disconnect" \
  "--min-frames $((fault_frames * 9 / 10))"
# Unplug/replug in a row (3 % of 300 images: ~9; the camera boots again after each): every good
# image delivered bit-exactly, every unplug counted once.
run seek_replug "--frames 300 --shutter-period 100 --fault-rate 0.03 --seed 5 --faults disconnect" \
  "--min-frames 270"
exit $failed
