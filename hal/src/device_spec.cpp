#include "bolo/hal/device_spec.hpp"

#include <algorithm>
#include <charconv>
#include <initializer_list>
#include <stdexcept>

namespace bolo::hal {
namespace {

int line_number(const std::string& key, const std::string& value) {
  int n = -1;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (ec != std::errc() || end != value.data() + value.size() || n < 0 || n > 4095)
    throw std::invalid_argument(key + "=" + value + ": expected a line number 0..4095");
  return n;
}

}  // namespace

std::vector<SpecOption> parse_spec_options(const std::string& text) {
  std::vector<SpecOption> options;
  if (text.empty()) return options;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    const std::size_t eq = item.find('=');
    if (eq == 0 || item.empty()) throw std::invalid_argument("'" + item + "': expected KEY=VALUE");
    options.push_back({item.substr(0, eq), eq == std::string::npos ? "" : item.substr(eq + 1)});
    at = comma + 1;
  }
  return options;
}

std::string unexpected_option(const SpecOption& option, const std::string& expected) {
  std::string text = "'";
  text += option.key;
  text += '=';
  text += option.value;
  text += "': expected ";
  text += expected;
  return text;
}

GpioConfig parse_gpio_spec(const std::string& text) {
  GpioConfig c;
  const std::size_t colon = text.find(':');
  c.chip = text.substr(0, colon);
  if (c.chip.empty()) throw std::invalid_argument("expected CHIP:sync=N,shutter=N,imminent=N");
  if (colon == std::string::npos) throw std::invalid_argument("no lines given (sync=N, shutter=N, imminent=N)");
  for (const SpecOption& option : parse_spec_options(text.substr(colon + 1))) {
    const auto& [key, value] = option;
    if (key == "sync") c.sync_line = line_number(key, value);
    else if (key == "shutter") c.shutter_line = line_number(key, value);
    else if (key == "imminent") c.ffc_imminent_line = line_number(key, value);
    else throw std::invalid_argument(unexpected_option(option, "sync=N, shutter=N or imminent=N"));
  }
  return c;
}

bool parse_lepton_option(const SpecOption& option, LeptonSettings& settings) {
  // The value's index among `words`; another value is refused naming them all.
  const auto pick = [&option](std::initializer_list<const char*> words) -> std::uint32_t {
    std::uint32_t i = 0;
    std::string expected;
    for (const char* word : words) {
      if (option.value == word) return i;
      expected += (i++ == 0 ? "" : "|");
      expected += word;
    }
    throw std::invalid_argument(unexpected_option(option, option.key + "=" + expected));
  };
  if (option.key == "gain") settings.gain_mode = pick({"high", "low", "auto"});
  else if (option.key == "radiometry") settings.radiometry = pick({"off", "on"});
  else if (option.key == "agc") settings.agc = pick({"off", "on"});
  else return false;
  return true;
}

bool usb_backend_available() {
#if defined(BOLO_HAVE_LIBUSB)
  return true;
#else
  return false;
#endif
}

}  // namespace bolo::hal
