#pragma once
// GPIO specs as `bolo capture --gpio` takes them: CHIP:sync=N,shutter=N,imminent=N (any subset);
// device strings are source specs (source_registry.hpp).
// Host code: parse errors throw std::invalid_argument with the reason (the caller names the flag).

#include <string>

#include "bolo/hal/gpio_lines.hpp"

namespace bolo::hal {

GpioConfig parse_gpio_spec(const std::string& text);
// Whether this build has the backend (libusb / libgpiod found at configure time).
bool usb_backend_available();

}  // namespace bolo::hal
