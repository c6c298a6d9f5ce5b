#pragma once
// Device strings, as `bolo capture --device` takes them:
//   v4l2:/dev/videoN        a UVC Y16 camera
//   usb:flirone             FLIR ONE Pro over libusb
//   usb:seek                Seek Thermal Compact / CompactPro over libusb
//   file:REC                a recording in the shared format (the recording player)
//   flirone-log:DIR         a captured FLIR ONE transfer log, through the same source as usb:flirone
// and GPIO specs as `--gpio` takes them: CHIP:sync=N,shutter=N,imminent=N (any subset).
// Host code: parse errors throw std::invalid_argument with the reason (the caller names the flag).

#include <string>

#include "bolo/hal/gpio_lines.hpp"

namespace bolo::hal {

enum class DeviceKind { v4l2, usb_flirone, usb_seek, file, flirone_log };

struct DeviceSpec {
  DeviceKind kind = DeviceKind::file;
  std::string path;  // the node, recording or log folder; empty for usb:*
};

DeviceSpec parse_device_spec(const std::string& text);
GpioConfig parse_gpio_spec(const std::string& text);
// Whether this build has the backend (libusb / libgpiod found at configure time).
bool usb_backend_available();

}  // namespace bolo::hal
