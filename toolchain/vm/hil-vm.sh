#!/usr/bin/env bash
# Hardware-in-loop VM: boots Debian's own kernel under qemu (TCG) with a busybox initramfs holding
# the given programs, their shared libraries and the USB-gadget/V4L2 modules, runs a scenario
# script inside and exits with the scenario's status.
#
#   hil-vm.sh --arch x86_64|aarch64 --scenario run.sh [--file PATH]... [--sysroot DIR]
#             [--timeout SECONDS] [--log FILE]
#
# Files given with --file land in /hil/ inside the VM; the scenario runs there as /hil/run.sh.
# Kernels and modules are fetched with `apt-get download` and unpacked into a cache
# (BOLO_HIL_CACHE, default ~/.cache/bolo-hil), never installed into the system.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
arch=x86_64
scenario=""
files=()
sysroot=""
timeout_s=600
log=""
while [ $# -gt 0 ]; do
  case "$1" in
    --arch) arch="$2"; shift 2 ;;
    --scenario) scenario="$2"; shift 2 ;;
    --file) files+=("$2"); shift 2 ;;
    --sysroot) sysroot="$2"; shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    --log) log="$2"; shift 2 ;;
    *) echo "hil-vm: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -n "$scenario" ] || { echo "hil-vm: --scenario is required" >&2; exit 2; }

cache="${BOLO_HIL_CACHE:-$HOME/.cache/bolo-hil}"
# shellcheck source=kernel-cache.sh
source "$here/kernel-cache.sh"
kernel_dir="$(hil_kernel_dir "$arch" "$cache")"
kver="$(cat "$kernel_dir/version")"
moddir="$kernel_dir/lib/modules/$kver"

work="$(mktemp -d "${TMPDIR:-/tmp}/bolo-hil.XXXXXX")"
trap 'rm -rf "$work"' EXIT
root="$work/root"
mkdir -p "$root"/{bin,sbin,dev,proc,sys,tmp,hil,lib/modules,etc}

# busybox: the host's for x86_64, the arm64 package's for aarch64.
busybox="$(hil_busybox "$arch" "$cache")"
cp "$busybox" "$root/bin/busybox"
for tool in sh mount umount insmod mkdir cat echo sleep poweroff ls grep mknod ln rm cp dd \
            head tail wc date seq true false kill test printf uname dmesg cmp od timeout cut \
            sed awk find mv chmod sync ps readlink basename dirname sort uniq env tr touch; do
  ln -sf busybox "$root/bin/$tool"
done

# Modules in dependency order (modules.dep lists a module's dependencies deepest last).
wanted=(configfs dummy_hcd libcomposite usb_f_fs usb_f_uvc uvcvideo vivid)
[ -f "$cache/$arch/gpio-sim/gpio-sim.ko" ] && extra_gpio_sim="$cache/$arch/gpio-sim/gpio-sim.ko" || extra_gpio_sim=""
order=()
add_module() {
  local path="$1" seen
  for seen in "${order[@]:-}"; do [ "$seen" = "$path" ] && return 0; done
  order+=("$path")
}
for name in "${wanted[@]}"; do
  line="$(grep -E "/${name}\.ko(\.[a-z]+)?:" "$moddir/modules.dep" | head -1 || true)"
  [ -n "$line" ] || { echo "hil-vm: module $name not in $kver" >&2; exit 3; }
  self="${line%%:*}"
  read -r -a deps <<<"${line#*:}"
  for ((i = ${#deps[@]} - 1; i >= 0; i--)); do add_module "${deps[$i]}"; done
  add_module "$self"
done
: >"$root/etc/modules"
for m in "${order[@]}"; do
  cp "$moddir/$m" "$root/lib/modules/"
  echo "$(basename "$m")" >>"$root/etc/modules"
done
# usb_f_uvc with bulk streaming (toolchain/vm/uvc-gadget.sh), where built, replaces Debian's
# (isochronous only); it has the same dependencies, packed above.
if [ -f "$cache/$arch/uvc-gadget/usb_f_uvc.ko" ]; then
  cp "$cache/$arch/uvc-gadget/usb_f_uvc.ko" "$root/lib/modules/usb_f_uvc.ko"
fi
if [ -n "$extra_gpio_sim" ]; then
  cp "$extra_gpio_sim" "$root/lib/modules/"
  echo gpio-sim.ko >>"$root/etc/modules"
fi
# raw_gadget (toolchain/vm/raw-gadget.sh), where built: after udc-core, packed above (dummy_hcd's).
if [ -f "$cache/$arch/raw-gadget/raw_gadget.ko" ]; then
  cp "$cache/$arch/raw-gadget/raw_gadget.ko" "$root/lib/modules/"
  echo raw_gadget.ko >>"$root/etc/modules"
fi
# v4l2loopback (toolchain/vm/v4l2loopback.sh), where built: its one dependency, videodev, is
# packed above (uvcvideo's).
if [ -f "$cache/$arch/v4l2loopback/v4l2loopback.ko" ]; then
  cp "$cache/$arch/v4l2loopback/v4l2loopback.ko" "$root/lib/modules/"
  echo v4l2loopback.ko >>"$root/etc/modules"
fi

# Programs, data and the shared libraries the programs need.
for f in "${files[@]}"; do cp -r "$f" "$root/hil/"; done
cp "$scenario" "$root/hil/run.sh"
cp "$here/hil-steps.sh" "$root/hil/steps.sh"
# The scenario's knobs (BOLO_HIL_*) travel into the VM.
env | grep '^BOLO_HIL_' | sed "s/'/'\\\\''/g; s/=\(.*\)/='\1'/; s/^/export /" >"$root/hil/env.sh" || true
chmod +x "$root/hil/run.sh"
hil_copy_libraries "$arch" "$root" "$sysroot" "${files[@]}"

cp "$here/init.sh" "$root/init"
chmod +x "$root/init"
(cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initrd.cpio"

case "$arch" in
  x86_64)
    qemu=(qemu-system-x86_64 -M pc -cpu max -m 1024 -smp 2
          -kernel "$kernel_dir/boot/vmlinuz" -initrd "$work/initrd.cpio"
          -append "console=ttyS0 quiet loglevel=4 panic=-1 tsc=reliable no_timer_check") ;;
  aarch64)
    qemu=(qemu-system-aarch64 -M virt -cpu cortex-a53 -m 1024 -smp 2
          -kernel "$kernel_dir/boot/vmlinuz" -initrd "$work/initrd.cpio"
          -append "console=ttyAMA0 quiet loglevel=4 panic=-1") ;;
  *) echo "hil-vm: unknown arch $arch" >&2; exit 2 ;;
esac
qemu+=(-accel tcg -nographic -no-reboot -nic none)

out="${log:-$work/serial.log}"
start=$(date +%s.%N)
status=0
# The serial console streams to our output as the VM runs (and to the log).
timeout --kill-after=10 "$timeout_s" "${qemu[@]}" </dev/null 2>&1 | sed -u 's/\r//g' | tee "$out"
status=${PIPESTATUS[0]}
end=$(date +%s.%N)
awk -v a="$arch" -v s="$start" -v e="$end" 'BEGIN { printf "hil-vm: %s VM ran %.1f s\n", a, e - s }'
[ $status -eq 124 ] && { echo "hil-vm: VM timed out after ${timeout_s}s" >&2; exit 1; }
result="$(grep -a '^HIL-RESULT ' "$out" | tail -1 || true)"
case "$result" in
  "HIL-RESULT pass") exit 0 ;;
  "HIL-RESULT skip"*) echo "hil-vm: skipped: ${result#HIL-RESULT skip}"; exit 77 ;;
  "") echo "hil-vm: the VM reported no result (qemu status $status)" >&2; exit 1 ;;
  *) echo "hil-vm: scenario failed: $result" >&2; exit 1 ;;
esac
