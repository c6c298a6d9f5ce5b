#!/usr/bin/env bash
# Builds gpio-sim.ko for the HIL VM's kernel out of tree (Debian's kernel has CONFIG_GPIO_SIM off),
# cached in $BOLO_HIL_CACHE/<arch>/gpio-sim/gpio-sim.ko, which hil-vm.sh then packs and loads.
# Sources: gpio-sim.c + gpiolib.h from Debian's linux-source-6.1, built against the matching
# linux-headers/kbuild packages unpacked into the cache (apt-get download, nothing installed).
# irq_sim.c (CONFIG_IRQ_SIM, also off) is built into the same module; its one call of the
# unexported irq_to_desc() becomes generic_handle_irq(), which runs the same handler.
#
# For aarch64 the module is cross-built (kernel-cache.sh: hil_module_make_args).
#
#   gpio-sim.sh [x86_64|aarch64]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
arch="${1:-x86_64}"
# shellcheck source=kernel-cache.sh
source "$here/kernel-cache.sh"
hil_module_start "$arch" gpio-sim
hil_module_cached gpio-sim.ko kver && exit 0

hil_module_kbuild

sources="$(hil_kernel_sources "$cache" "$series")"
cp "$sources"/drivers/gpio/gpiolib*.h "$sources/kernel/irq/irq_sim.c" "$out/"
cp "$sources/drivers/gpio/gpio-sim.c" "$out/gpio-sim-main.c"
grep -q 'handle_simple_irq(irq_to_desc(irqnum));' "$out/irq_sim.c" ||
  { echo "gpio-sim: irq_sim.c changed upstream; check the irq_to_desc replacement" >&2; exit 1; }
sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' "$out/irq_sim.c"
printf 'obj-m := gpio-sim.o\ngpio-sim-y := gpio-sim-main.o irq_sim.o\n' >"$out/Kbuild"
make -s -C "$headers" M="$out" "${HIL_MAKE_ARGS[@]}" modules >&2
echo "$kver" >"$out/kver"
rm -rf "$module_root"
echo "$out/gpio-sim.ko"
