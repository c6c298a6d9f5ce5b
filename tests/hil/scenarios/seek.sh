#!/bin/sh
# HIL scenario, run inside the VM: the Seek Compact emulator on FunctionFS, the host side
# through the project's SeekSource: 1) images without faults, a shutter cycle after the boot and
# every 100 images: none lost, every image bit-exact equal to the emulator's own image minus the
# latest shutter frame (the offset pattern changes at each shutter event), no start-up request
# refused, every shutter frame an FFC event, the start-up frame's 5 dead pixels found; 2) 1 % of each fault kind, stalls and unplug/replug included; 3) ~9
# unplug/replug cycles in a row; 4) the real-camera check (no send log): passes a clean stream,
# fails one with frame-id jumps and duplicates; 5) the CompactPro (its own start-up sequence,
# 342x260 frames, 320x240 delivered): a clean run and one with 3 % faults.
# BOLO_HIL_SEEK_FRAMES (run-hil-test.sh: 1000; 10000 for the endurance run) sets the clean
# run's length; the fault run streams a quarter of it.
# vm-arch: x86_64
# device: usb:seek
# real: hil_seek_hal --real --frames "${BOLO_HIL_SEEK_FRAMES:-10000}"
frames="${BOLO_HIL_SEEK_FRAMES:-10000}"
fault_frames=$((frames / 4))
failed=0

run() {  # name, emulator arguments, host arguments (default: against the emulator's send log)
  name="$1"
  host_args="${3:-}"
  case "$host_args" in
    --real*) ;;
    *) host_args="--send-log /tmp/$name.log --done /tmp/$name.done $host_args" ;;
  esac
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  ./seek_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" \
    --done "/tmp/$name.done" --finished "/tmp/$name.finished" $2 &
  emulator=$!
  if [ "${4:-}" = must-fail ]; then
    ! ./hil_seek_hal $host_args || { echo "HIL-STEP $name: the host check passed a faulty stream"; failed=1; }
  else
    ./hil_seek_hal $host_args || failed=1
  fi
  touch "/tmp/$name.finished"
  # A host check that is meant to fail may stop before the emulator has sent everything.
  wait $emulator || [ "${4:-}" = must-fail ] || { echo "HIL-STEP $name: the emulator failed"; failed=1; }
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}

run seek_clean "--frames $frames --shutter-period 100" \
  "--min-frames $frames --shutters $((1 + (frames - 1) / 100)) --dead-pixels 5"
run seek_faults "--frames $fault_frames --shutter-period 100 --fault-rate 0.01 --seed 3 \
  --faults short_transfer,timeout,frame_id_jump,duplicate,stall,disconnect" \
  "--min-frames $((fault_frames * 9 / 10))"
# Unplug/replug in a row (3 % of 300 images: ~9; the camera boots again after each): every good
# image delivered bit-exactly, every unplug counted once.
run seek_replug "--frames 300 --shutter-period 100 --fault-rate 0.03 --seed 5 --faults disconnect" \
  "--min-frames 270"
# The real-camera check (BOLO_HIL_DEVICE=usb:seek) against the emulator without faults, so that
# mode is exercised here too: it must pass on a clean stream without a send log.
run seek_as_camera "--frames 300 --shutter-period 100" "--real --frames 300"
# ...and it must fail one with frame-id jumps and duplicates (images lost or repeated).
run seek_as_faulty_camera "--frames 300 --shutter-period 100 --fault-rate 0.03 --seed 7 \
  --faults frame_id_jump,duplicate" "--real --frames 280" must-fail
# The CompactPro: 176 start-up requests, 13680-byte chunks, the active area 320x240 at (1, 4).
run seek_pro_clean "--model compactpro --frames 300 --shutter-period 100" \
  "--min-frames 300 --shutters 3 --dead-pixels 5"
run seek_pro_faults "--model compactpro --frames 300 --shutter-period 100 --fault-rate 0.03 --seed 11 \
  --faults short_transfer,timeout,stall,disconnect,duplicate" "--min-frames 270"
exit $failed
