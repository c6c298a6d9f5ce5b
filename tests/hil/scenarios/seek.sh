#!/bin/sh
# HIL scenario, run inside the VM: the Seek Compact emulator on FunctionFS, the host side
# through the project's SeekSource: 1) images without faults, shutter cycles every 100 images:
# none lost, every image bit-exact, every shutter frame an FFC event, the start-up frame's 5
# dead pixels found; 2) 1 % of the faults the backend survives.
# BOLO_HIL_SEEK_FRAMES (run-hil-test.sh: 3000 on x86-64, 1000 in the arm64 VM) sets the clean
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
  --faults short_transfer,timeout,frame_id_jump,duplicate" "--min-frames $((fault_frames * 9 / 10))"
# Stall and replug through the backend's libusb transport: expected to fail as for the FLIR ONE
# (docs/hil.md); when this passes, the step fails so the faults move into seek_faults above.
saved=$failed
failed=0
run seek_stall_replug "--frames 300 --shutter-period 100 --fault-rate 0.02 --seed 5 --faults stall,disconnect" ""
if [ $failed -eq 0 ]; then
  echo "HIL-STEP seek_stall_replug: FAIL it passes now: move stall,disconnect into seek_faults"
  failed=1
else
  echo "HIL-STEP seek_stall_replug: known failure of the Seek backend's transport (docs/hil.md)"
  failed=$saved
fi
exit $failed
