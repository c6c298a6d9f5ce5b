#pragma once
// GPIO specs as `bolo capture --gpio` takes them: CHIP:sync=N,shutter=N,imminent=N (any subset);
// device strings are source specs (source_registry.hpp), whose options (v4l2:/dev/video0?format=GREY)
// are the same KEY=VALUE list.
// Host code: parse errors throw std::invalid_argument with the reason (the caller names the flag).

#include <string>
#include <vector>

#include "bolo/hal/gpio_lines.hpp"

namespace bolo::hal {

struct SpecOption {
  std::string key, value;
};
// "k=v,k2=v2" in order ("" gives none; a bare "k" has an empty value); an item without a key throws.
std::vector<SpecOption> parse_spec_options(const std::string& text);
// The refusal of an option a spec does not take: "'key=value': expected EXPECTED".
std::string unexpected_option(const SpecOption& option, const std::string& expected);

GpioConfig parse_gpio_spec(const std::string& text);
// Whether this build has the backend (libusb / libgpiod found at configure time).
bool usb_backend_available();

}  // namespace bolo::hal
