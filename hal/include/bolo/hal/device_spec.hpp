#pragma once
// GPIO specs as `bolo capture --gpio` takes them: CHIP:sync=N,shutter=N,imminent=N (any subset);
// device strings are source specs (source_registry.hpp), whose options (v4l2:/dev/video0?format=GREY,
// a PureThermal's Lepton settings v4l2:/dev/video0?gain=low,radiometry=on,agc=off) are the same
// KEY=VALUE list.
// Host code: parse errors throw std::invalid_argument with the reason (the caller names the flag).

#include <cstdint>
#include <optional>
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

// Lepton settings a v4l2: spec asks a PureThermal for, in the values the Lepton SDK gives them
// (purethermal_xu.hpp): gain mode 0 high, 1 low, 2 auto; radiometry and AGC 0 off, 1 on.
struct LeptonSettings {
  std::optional<std::uint32_t> gain_mode, radiometry, agc;
  bool empty() const { return !gain_mode && !radiometry && !agc; }
};
// The options' words: gain=high|low|auto, radiometry=on|off, agc=on|off.
inline constexpr const char* kLeptonOptions = "gain=high|low|auto, radiometry=on|off, agc=on|off";
// Takes `option` into `settings` when its key is gain, radiometry or agc (true); false for another
// key; an unknown value throws naming the option and the words it takes.
bool parse_lepton_option(const SpecOption& option, LeptonSettings& settings);
// Whether this build has the backend (libusb / libgpiod found at configure time).
bool usb_backend_available();

}  // namespace bolo::hal
