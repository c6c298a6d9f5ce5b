#!/bin/sh
# PID 1 of the HIL VM: mounts the kernel's file systems, loads the modules the harness packed
# (in dependency order), runs /hil/run.sh and reports its status on the serial console as one
# "HIL-RESULT pass|fail ...|skip ..." line, then powers off.
export PATH=/bin:/sbin LD_LIBRARY_PATH=/lib HOME=/tmp
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t tmpfs tmpfs /tmp
echo "HIL-BOOT $(cut -d' ' -f1 /proc/uptime) s"

for m in $(cat /etc/modules); do
  # vivid: one instance, video capture only, webcam input (discrete sizes: on the TV input its
  # 16384x8640 maximum is what a source that picks the largest size gets, and the VM runs out
  # of memory).
  case "$m" in
    vivid.ko) args="n_devs=1 node_types=0x1 input_types=0x0" ;;
    # One loopback node at a fixed number, for `bolo run --sink v4l2:/dev/video42` (uvc.sh).
    v4l2loopback.ko) args="devices=1 video_nr=42 max_buffers=8" ;;
    *) args="" ;;
  esac
  insmod "/lib/modules/$m" $args || echo "HIL-WARN insmod $m failed"
done
mount -t configfs none /sys/kernel/config 2>/dev/null
echo "HIL-READY $(cut -d' ' -f1 /proc/uptime) s"

cd /hil
[ -f /hil/env.sh ] && . /hil/env.sh
sh /hil/run.sh
status=$?
case $status in
  0) echo "HIL-RESULT pass" ;;
  77) echo "HIL-RESULT skip $(cat /tmp/skip-reason 2>/dev/null)" ;;
  *) echo "HIL-RESULT fail (status $status)" ;;
esac
echo "HIL-END $(cut -d' ' -f1 /proc/uptime) s"
poweroff -f
