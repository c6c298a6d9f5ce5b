#!/bin/sh
# HIL scenario, run inside the VM: the PureThermal emulator (UVC Y16, 160x120 and 160x122 with
# Lepton telemetry rows) on the configfs UVC gadget function (usb_f_uvc bulk build of
# toolchain/vm/uvc-gadget.sh), frames of the lepton3-possum recording (simulated ones without
# ../shared); the host side through the real uvcvideo driver and the project's V4l2Source:
# 1) 160x122 without faults, FFC every 100 frames: none lost, every image and telemetry counter
# bit-exact, every FFC seen; 2) 160x120 (no telemetry rows); 3) 1 % faults, drawn among short frame,
# duplicate, silence; 4) unplug/replug (2 % of 300 frames); 5) where the CLI is built and the
# recording is there: `bolo capture --device v4l2:/dev/videoN --shutter-at 80` of the recording
# played once must hold exactly its pixels, and its frames.csv one FFC, in the frame the emulator
# ran the Lepton Run FFC into; 6) the real-camera check (`hil_uvc_hal --real`, no send log): passes a
# clean stream, fails one with short frames; 7) where v4l2loopback is built, `bolo run` from the
# camera into it, read back bit for bit against `bolo correct` of the recording; 8) the Lepton
# command interface over the extension units (hil_uvc_xu: detection by descriptors, temperatures,
# gain mode / radiometry / AGC from a v4l2: spec read back, the source's shutter = SYS Run FFC in
# the stream at the frame the emulator put it in; the emulator refused nothing; `bolo devices`
# shows the temperatures), and a board that refuses every extension-unit request must fail it
# (`bolo devices`: unread).
# BOLO_HIL_UVC_FRAMES (run-hil-test.sh: 1000; 10000 for the endurance run) sets the clean run's length; the fault
# run streams a quarter of it.
# device: v4l2
# real: hil_uvc_hal --real --device "${BOLO_HIL_DEVICE#v4l2:}" --size "${BOLO_HIL_UVC_SIZE:-160x120}" --frames "${BOLO_HIL_UVC_FRAMES:-10000}"
if [ ! -e /sys/module/usb_f_uvc/parameters/bulk_payload ]; then
  echo "Debian's isochronous-only usb_f_uvc is loaded, not the bulk build (toolchain/vm/uvc-gadget.sh failed or was not run)" >/tmp/skip-reason
  exit 77
fi
frames="${BOLO_HIL_UVC_FRAMES:-10000}"
fault_frames=$((frames / 4))
recording=""
if [ -d ./lepton3-possum ]; then
  recording="--recording ./lepton3-possum"
else
  echo "uvc: no lepton3-possum recording (../shared/data absent): simulated frames"
fi
failed=0
. ./steps.sh

run() {  # name, emulator arguments, host arguments[, must-fail]
  name="$1"
  hil_skip_step "$name" && return 0
  host_args="$3"
  case "$host_args" in
    --real*) ;;
    *) host_args="--send-log /tmp/$name.log --done /tmp/$name.done $host_args" ;;
  esac
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  # --credit/--progress: the emulator stays at most 8 frames ahead of what the host program has
  # delivered (it has 16 buffers), so uvcvideo always has a buffer: a lost frame is the stack's.
  ./uvc_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" \
    --done "/tmp/$name.done" --finished "/tmp/$name.finished" --credit "/tmp/$name.progress:8" $recording $2 &
  emulator=$!
  if [ "${4:-}" = must-fail ]; then
    ! ./hil_uvc_hal --progress "/tmp/$name.progress" --buffers 16 $host_args ||
      { echo "HIL-STEP $name: the host check passed a faulty stream"; failed=1; }
  else
    ./hil_uvc_hal --progress "/tmp/$name.progress" --buffers 16 $host_args || failed=1
  fi
  touch "/tmp/$name.finished"
  # A host check that is meant to fail may stop before the emulator has sent everything.
  wait $emulator || [ "${4:-}" = must-fail ] || { echo "HIL-STEP $name: the emulator failed"; failed=1; }
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
}

run uvc_clean "--frames $frames --ffc-period 100" "--size 160x122 --min-frames $frames --ffc-period 100"
run uvc_plain "--frames 300" "--size 160x120 --min-frames 300"
run uvc_faults "--frames $fault_frames --ffc-period 100 --fault-rate 0.01 --seed 3 \
  --faults short_transfer,duplicate,timeout" "--size 160x122 --min-frames $((fault_frames * 9 / 10)) --ffc-period 100"
run uvc_replug "--frames 300 --fault-rate 0.02 --seed 5 --faults disconnect" \
  "--size 160x122 --min-frames 250 --lost-per-unplug 4"
# The real-camera check (BOLO_HIL_DEVICE=v4l2:/dev/videoN) against the emulator: a clean stream
# passes, one with short frames (uvcvideo drops them: sequence gaps) must fail.
run uvc_as_camera "--frames 300 --ffc-period 100" "--real --frames 300 --size 160x122"
run uvc_as_faulty_camera "--frames 300 --ffc-period 100 --fault-rate 0.03 --seed 7 --faults short_transfer" \
  "--real --frames 280 --size 160x122" must-fail
# The host's uvcvideo capture node of the emulated camera (not the gadget's output node, not
# uvcvideo's metadata node).
host_node() {
  for d in /sys/class/video4linux/video*; do
    grep -q PureThermal "$d/name" 2>/dev/null || continue
    [ -e "$d/function_name" ] && continue
    [ "$(cat "$d/index")" = 0 ] && { echo "/dev/$(basename "$d")"; return 0; }
  done
  return 1
}
# The emulator's node once uvcvideo has bound it (up to 10 s), or empty.
wait_host_node() {
  for _ in $(seq 100); do host_node && return 0; sleep 0.1; done
}

if [ -x ./bolo ] && [ -n "$recording" ]; then
  name=uvc_capture
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  # 160 frames = the recording once; 30 frames/s: bolo capture keeps up without a credit.
  ./uvc_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" --done "/tmp/$name.done" \
    --finished "/tmp/$name.finished" --xu-log "/tmp/$name.xu" $recording --frames 160 --fps 30 &
  emulator=$!
  node="$(wait_host_node)"
  if [ -z "$node" ]; then
    echo "HIL-STEP $name: no uvcvideo node of the emulator"; failed=1
  elif ./bolo capture --device "v4l2:$node" --out /tmp/uvc-rec --frames 160 --shutter-at 80 --no-progress; then
    # The pixels (the .npy header's padding may differ): the last 160x120x160x2 bytes.
    tail -c 6144000 /tmp/uvc-rec/frames.npy >/tmp/uvc-rec.pixels
    tail -c 6144000 lepton3-possum/frames.npy >/tmp/possum.pixels
    if cmp /tmp/uvc-rec.pixels /tmp/possum.pixels; then
      echo "HIL-STEP $name: 160 frames through bolo capture, pixels identical to real/lepton3-possum"
    else
      echo "HIL-STEP $name: bolo capture's frames differ from the recording"; failed=1
    fi
    cat /tmp/uvc-rec/capture.json
    # frames.csv: index,t_s,exposure_s,readout_s,ffc,...; the emulator's "ffc INDEX COUNTER".
    csv_ffc="$(awk -F, 'NR > 1 && $5 == 1 { printf "%s%s", s, $1; s = " " }' /tmp/uvc-rec/frames.csv)"
    sent_ffc="$(awk '$1 == "ffc" { printf "%s%s", s, $2; s = " " }' "/tmp/$name.xu")"
    if [ -n "$csv_ffc" ] && [ "$csv_ffc" = "$sent_ffc" ]; then
      echo "HIL-STEP $name: --shutter-at 80: one FFC, in frame $csv_ffc as the emulator ran it"
    else
      echo "HIL-STEP $name: --shutter-at 80: FFC frames in frames.csv '$csv_ffc', run by the emulator '$sent_ffc'"; failed=1
    fi
  else
    echo "HIL-STEP $name: bolo capture failed"; failed=1
  fi
  touch "/tmp/$name.finished"
  wait $emulator
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
fi
# 7) `bolo run` from the emulated camera into a v4l2loopback output node (/dev/video42,
# toolchain/vm/v4l2loopback.sh), read back through its capture side by hil_loopback_reader: every
# frame read equals, bit for bit, the frame `bolo correct` makes of the recording with the same
# flags (--nominal-fps 0.26: no time-gap breaks from the VM's jitter); then SIGINT stops the run,
# which must exit 0.
if [ -x ./bolo ] && [ -x ./hil_loopback_reader ] && [ -n "$recording" ]; then
  name=uvc_run_loopback
  echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
  if [ ! -e /dev/video42 ]; then
    echo "HIL-STEP $name: no v4l2loopback node /dev/video42 (toolchain/vm/v4l2loopback.sh not built): skipped"
  else
    flags="--tau-h 0.012 --tau-c 0.012 --exposure 0.01 --readout 0.1 --nominal-fps 0.26"
    ./bolo correct ./lepton3-possum /tmp/expected $flags --no-progress >/dev/null || failed=1
    ./uvc_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" --done "/tmp/$name.done" \
      --finished "/tmp/$name.finished" $recording --frames 160 --fps 9 &
    emulator=$!
    node="$(wait_host_node)"
    if [ -z "$node" ]; then
      echo "HIL-STEP $name: no uvcvideo node of the emulator"; failed=1
    else
      ./bolo run --device "v4l2:$node" --sink v4l2:/dev/video42 $flags 2>"/tmp/$name.err" &
      runner=$!
      ./hil_loopback_reader --device /dev/video42 --expected /tmp/expected --min-frames 120 || failed=1
      kill -INT $runner
      wait $runner || { echo "HIL-STEP $name: bolo run did not exit 0 after SIGINT"; failed=1; }
      cat "/tmp/$name.err"
    fi
    touch "/tmp/$name.finished"
    wait $emulator
  fi
  echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
fi
# 8) The Lepton command interface (60 frames, the FFC requested before frame 20), then the same
# against an emulator told to refuse: hil_uvc_xu must fail and the emulator must have refused.
if [ -x ./hil_uvc_xu ]; then
  for name in uvc_xu uvc_xu_refused; do
    echo "HIL-STEP $name start $(cut -d' ' -f1 /proc/uptime)"
    refuse=""
    [ "$name" = uvc_xu_refused ] && refuse=--refuse-xu
    ./uvc_emulator --name "$name" --log "/tmp/$name.log" --ready "/tmp/$name.ready" --done "/tmp/$name.done" \
      --finished "/tmp/$name.finished" --credit "/tmp/$name.progress:3" --xu-log "/tmp/$name.xu" \
      --frames 60 $refuse &
    emulator=$!
    want_temps="FPA 26.85 C, housing 28.35 C"
    if [ -z "$refuse" ]; then
      ./hil_uvc_xu --xu-log "/tmp/$name.xu" --frames 60 --shutter-at 20 --progress "/tmp/$name.progress" || failed=1
    else
      want_temps="FPA unread, housing unread"
      if ./hil_uvc_xu --xu-log "/tmp/$name.xu" --frames 60 --shutter-at 20 --progress "/tmp/$name.progress"; then
        echo "HIL-STEP $name: the Lepton check passed a board that refuses its commands"; failed=1
      fi
    fi
    # `bolo devices` lists the board with the temperatures it reads through the extension unit.
    if [ -x ./bolo ]; then
      ./bolo devices >"/tmp/$name.devices" 2>&1
      if grep -q "PureThermal (Lepton commands): $want_temps" "/tmp/$name.devices"; then
        echo "HIL-STEP $name: bolo devices: $want_temps"
      else
        echo "HIL-STEP $name: bolo devices does not say '$want_temps':"; cat "/tmp/$name.devices"; failed=1
      fi
    fi
    touch "/tmp/$name.finished"
    wait $emulator || [ -n "$refuse" ] || { echo "HIL-STEP $name: the emulator failed"; failed=1; }
    summary="$(grep '^xu ' "/tmp/$name.xu")"
    echo "HIL-STEP $name: emulator $summary"
    case "$refuse:$summary" in
      :*" refused 0 "*" ffc 1") ;;
      --refuse-xu:*" refused 0 "*) echo "HIL-STEP $name: the emulator refused nothing"; failed=1 ;;
      --refuse-xu:*) ;;
      *) echo "HIL-STEP $name: want refused 0, ffc 1"; failed=1 ;;
    esac
    echo "HIL-STEP $name end $(cut -d' ' -f1 /proc/uptime)"
  done
fi
exit $failed
