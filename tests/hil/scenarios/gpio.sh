#!/bin/sh
# HIL scenario, run inside the VM: gpio-sim (built out of tree by toolchain/vm/gpio-sim.sh) makes
# a simulated GPIO chip through configfs; the project's libgpiod backend must list it with its
# label and line count (`bolo devices`). Skipped without the module or the CLI.
# device: gpio
# real: echo "gpio on a real board: run 'bolo devices' (docs/hil.md)"; exit 77
grep -q '^gpio_sim ' /proc/modules || { echo "no gpio-sim module in this VM" >/tmp/skip-reason; exit 77; }
[ -x ./bolo ] || { echo "no bolo CLI in this build" >/tmp/skip-reason; exit 77; }
chip=/sys/kernel/config/gpio-sim/hil
mkdir "$chip" "$chip/bank0" || exit 1
echo 8 >"$chip/bank0/num_lines"
echo hil-bank >"$chip/bank0/label"
echo 1 >"$chip/live" || exit 1
name="$(cat "$chip/bank0/chip_name")"
./bolo devices >/tmp/devices.txt
cat /tmp/devices.txt
grep -Eq "^  $name +hil-bank +8 lines" /tmp/devices.txt
