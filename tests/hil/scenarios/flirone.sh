#!/bin/sh
# HIL scenario, run inside the VM: the FLIR ONE emulator on Raw Gadget (raw_gadget.ko, dummy_hcd),
# which streams only after the public drivers' start-up (SET_CONFIGURATION 3, SET_INTERFACE in
# their order) and refuses any other request; every host below must have none refused. 0) The
# vendor request alone (a wrong start-up) is stalled and gets no frame. The host
# side through libusb: 1) the real capture replayed, delivered bit-exactly; 2) simulated frames
# with 1 % injected faults of every kind: every fault counted, every good frame delivered
# bit-exactly, replug recovered within 2 s. Then through the project's FlirOneSource: 3) simulated
# frames without faults: none lost, every image bit-exact; 4) with the faults (unplug/replug
# included) every good image delivered bit-exactly, every unplug counted; 5) ~30 replugs in a row;
# 6) the real-camera check passes a clean stream and fails a faulty one.
# BOLO_HIL_FRAMES (run-hil-test.sh: 1000; 10000 for the endurance run) sets the length.
# device: usb:flirone
# real: hil_flirone_hal --real --frames ${BOLO_HIL_FRAMES:-10000}
frames="${BOLO_HIL_FRAMES:-10000}"
failed=0
. ./steps.sh
if [ ! -e /dev/raw-gadget ]; then
  echo "no /dev/raw-gadget (raw_gadget.ko not built: toolchain/vm/raw-gadget.sh)" >/tmp/skip-reason
  exit 77
fi

run() {  # name, emulator arguments, host arguments
  name="$1"
  hil_skip_step "$name" && return 0
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  ./flirone_emulator --capture flirone-pro --log "/tmp/$name.log" \
    --ready "/tmp/$name.ready" --done "/tmp/$name.done" --finished "/tmp/$name.finished" $2 &
  emulator=$!
  ./hil_flirone --send-log "/tmp/$name.log" --done "/tmp/$name.done" $3 || failed=1
  touch "/tmp/$name.finished"
  wait $emulator || { echo "HIL-STEP $name: the emulator failed (status $?: 4 = requests refused)"; failed=1; }
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}

# A wrong start-up: the vendor request alone (what the emulator once accepted) is stalled, no
# frame flows, and the emulator ends with status 4 (requests refused).
echo "HIL-STEP wrong_start start $(cut -d' ' -f1 /proc/uptime)"
./flirone_emulator --capture flirone-pro --frames 10 --jpeg-bytes 0 --log /tmp/wrong_start.log \
  --ready /tmp/wrong_start.ready --done /tmp/wrong_start.done --finished /tmp/wrong_start.finished &
emulator=$!
./hil_flirone --wrong-start || failed=1
for d in /sys/bus/usb/devices/*; do  # the link speed the emulated camera got (480: high speed)
  grep -qs 09cb "$d/idVendor" && echo "HIL-STEP wrong_start: 09cb:1996 at $(cat "$d/speed") Mb/s"
done
touch /tmp/wrong_start.finished
wait $emulator
status=$?
[ $status -eq 4 ] || { echo "HIL-STEP wrong_start: the emulator exited $status, want 4 (requests refused)"; failed=1; }
echo "HIL-STEP wrong_start end $(cut -d' ' -f1 /proc/uptime)"

run replay "--replay" "--capture flirone-pro"
run faults "--frames $frames --jpeg-bytes 0 --fault-rate 0.01 --faults all --seed 7" "--min-frames $((frames * 9 / 10))"
if [ ! -x ./hil_flirone_hal ]; then  # without the project's backend: the clean run on our reader
  run clean "--frames $frames --jpeg-bytes 0" "--min-frames $frames"
fi
# `bolo capture --device usb:flirone` from the emulated camera replaying the real capture must
# write the frames of the shared recording made from that capture, byte for byte.
if [ -x ./bolo ] && [ -d flirone-lepton-telemetry ]; then
  echo "HIL-STEP bolo_capture start $(cut -d' ' -f1 /proc/uptime)"
  ./flirone_emulator --replay --capture flirone-pro --log /tmp/capture.log \
    --ready /tmp/capture.ready --done /tmp/capture.done --finished /tmp/capture.finished &
  emulator=$!
  # bolo opens the camera once: wait until the host has enumerated it.
  for _ in $(seq 100); do grep -qs 09cb /sys/bus/usb/devices/*/idVendor && break; sleep 0.1; done
  sleep 0.3
  if ./bolo capture --device usb:flirone --out /tmp/capture-rec --frames 20 --no-progress &&
     cmp /tmp/capture-rec/frames.npy flirone-lepton-telemetry/frames.npy; then
    echo "HIL-STEP bolo_capture: 20 frames, frames.npy identical to real/flirone-lepton-telemetry"
  else
    echo "HIL-STEP bolo_capture: FAIL"
    failed=1
  fi
  touch /tmp/capture.finished
  wait $emulator || { echo "HIL-STEP bolo_capture: the emulator failed (status $?: 4 = requests refused)"; failed=1; }
  echo "HIL-STEP bolo_capture end $(cut -d' ' -f1 /proc/uptime)"
else
  echo "HIL-STEP bolo_capture: skipped (no bolo CLI in this build, or no shared recording)"
fi

run_hal() {  # name, emulator arguments, host arguments [must-fail]: through the project's FlirOneSource
  name="$1"
  hil_skip_step "$name" && return 0
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  ./flirone_emulator --capture flirone-pro --log "/tmp/$name.log" \
    --ready "/tmp/$name.ready" --done "/tmp/$name.done" --finished "/tmp/$name.finished" $2 &
  emulator=$!
  if [ "${4:-}" = must-fail ]; then
    ./hil_flirone_hal --send-log "/tmp/$name.log" --done "/tmp/$name.done" $3 &&
      { echo "HIL-STEP $name: FAIL the check passed a faulty stream"; failed=1; }
  else
    ./hil_flirone_hal --send-log "/tmp/$name.log" --done "/tmp/$name.done" $3 || failed=1
  fi
  touch "/tmp/$name.finished"
  wait $emulator
  status=$?
  # A must-fail reader stops before the emulator has sent everything (status 3, expected there);
  # refused requests (status 4) fail every step.
  if [ $status -eq 4 ] || { [ $status -ne 0 ] && [ "${4:-}" != must-fail ]; }; then
    echo "HIL-STEP $name: the emulator failed (status $status: 4 = requests refused)"
    failed=1
  fi
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}
if [ -x ./hil_flirone_hal ]; then
  run_hal hal_clean "--frames $frames --jpeg-bytes 0" "--min-frames $frames"
  run_hal hal_faults "--frames $((frames / 4)) --jpeg-bytes 0 --fault-rate 0.01 --seed 11 \
    --faults short_transfer,corrupt,timeout,frame_id_jump,duplicate,stall,disconnect" \
    "--min-frames $((frames / 5))"
  # Many unplug/replug cycles in a row (3 % of 1000 frames: ~30): every good frame delivered,
  # every unplug counted once, each recovered within 2 s. This is the step that found the
  # transport's use-after-free after a replug (docs/hil.md).
  run_hal hal_replug "--frames 1000 --jpeg-bytes 0 --fault-rate 0.03 --seed 5 --faults disconnect" \
    "--min-frames 900"
  # The real-camera check (BOLO_HIL_DEVICE=usb:flirone) against the emulator without faults: it
  # must pass a clean stream without a send log, and fail one with corrupt packets and counter
  # jumps. Its logic does not differ by architecture: x86-64 only.
  if [ "$(uname -m)" = x86_64 ]; then
    run_hal flirone_as_camera "--frames 300 --jpeg-bytes 0" "--real --frames 300"
    run_hal flirone_as_faulty_camera "--frames 300 --jpeg-bytes 0 --fault-rate 0.03 --seed 7 \
      --faults corrupt,frame_id_jump" "--real --frames 280" must-fail
  fi
else
  echo "HIL-STEP hal: skipped, the HAL was built without libusb"
fi
exit $failed

