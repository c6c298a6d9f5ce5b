#!/bin/sh
# HIL scenario, run inside the VM: gpio-sim (built out of tree by toolchain/vm/gpio-sim.sh) makes
# a simulated GPIO chip through configfs. 1) hil_gpio drives its lines through the project's
# libgpiod backend and GpioSyncedSource: frame-sync edges made through the sim's `pull`
# attributes arrive timestamped and matched to frames, "FFC imminent" marks the frames it is held
# over, shutter pulses toggle the output line (read back through the sim's `value`) and mark the
# next frame as an FFC frame. 2) `bolo devices` lists the chip with its label and line count.
# Skipped without the module, or without both programs.
# vm-arch: x86_64
# device: gpio
# real: hil_gpio_camera --device "$BOLO_HIL_DEVICE" --gpio "$BOLO_HIL_GPIO" --frames "${BOLO_HIL_GPIO_FRAMES:-300}"
grep -q '^gpio_sim ' /proc/modules || { echo "no gpio-sim module in this VM" >/tmp/skip-reason; exit 77; }
[ -x ./hil_gpio ] || [ -x ./bolo ] || { echo "neither hil_gpio nor the bolo CLI in this build" >/tmp/skip-reason; exit 77; }
chip=/sys/kernel/config/gpio-sim/hil
mkdir "$chip" "$chip/bank0" || exit 1
echo 8 >"$chip/bank0/num_lines"
echo hil-bank >"$chip/bank0/label"
echo 1 >"$chip/live" || exit 1
name="$(cat "$chip/bank0/chip_name")"
failed=0
if [ -x ./hil_gpio ]; then
  echo "HIL-STEP gpio_lines start $(cut -d' ' -f1 /proc/uptime)"
  ./hil_gpio --chip "$name" --sysfs "/sys/bus/gpio/devices/$name" --frames "${BOLO_HIL_GPIO_FRAMES:-1000}" || failed=1
  echo "HIL-STEP gpio_lines end $(cut -d' ' -f1 /proc/uptime)"
else
  echo "HIL-STEP gpio_lines: skipped (no hil_gpio: the HAL was built without libgpiod)"
fi
if [ -x ./bolo ]; then
  ./bolo devices >/tmp/devices.txt
  cat /tmp/devices.txt
  grep -Eq "^  $name +hil-bank +8 lines" /tmp/devices.txt || { echo "HIL-STEP gpio_list: FAIL"; failed=1; }
else
  echo "HIL-STEP gpio_list: skipped (no bolo CLI in this build)"
fi
# The real-device check's program (BOLO_HIL_GPIO) on the sim's lines, with a recording as the
# camera: it opens both through the HAL, and its shutter pulse marks exactly the frame after it.
# A recording's time stamps are not the host's clock, so no sync line here (hil_gpio covers sync).
if [ -x ./hil_gpio_camera ] && [ -x ./bolo ]; then
  echo "HIL-STEP gpio_camera start $(cut -d' ' -f1 /proc/uptime)"
  ./bolo simulate --out /tmp/gpio-camera --frames 40 --size 32x24 >/dev/null 2>&1 &&
    ./hil_gpio_camera --device file:/tmp/gpio-camera --gpio "$name:shutter=0,imminent=2" --frames 40 || failed=1
  echo "HIL-STEP gpio_camera end $(cut -d' ' -f1 /proc/uptime)"
fi
exit $failed
