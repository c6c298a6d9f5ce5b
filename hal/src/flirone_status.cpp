#include "bolo/hal/flirone_status.hpp"

#include <cstddef>
#include <string_view>

namespace bolo::hal {
namespace {

struct Cursor {
  std::span<const std::uint8_t> text;
  std::size_t pos = 0;
  bool done() const { return pos >= text.size() || text[pos] == 0; }
  char peek() const { return done() ? '\0' : static_cast<char>(text[pos]); }
  void skip_space() {
    while (!done() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) ++pos;
  }
  bool eat(char c) {
    skip_space();
    if (peek() != c) return false;
    ++pos;
    return true;
  }
};

// A string body after its opening quote, into `out` (NUL-terminated, truncation refused).
// Escapes are kept verbatim: the fields read here never contain them.
bool read_string(Cursor& c, char* out, std::size_t capacity) {
  std::size_t n = 0;
  while (!c.done()) {
    const char ch = c.peek();
    ++c.pos;
    if (ch == '"') {
      if (out) out[n] = '\0';
      return true;
    }
    if (ch == '\\') {
      if (c.done()) return false;
      ++c.pos;
      continue;
    }
    if (out) {
      if (n + 1 >= capacity) return false;
      out[n++] = ch;
    }
  }
  return false;
}

// A JSON number as a fixed-point integer with `decimals` fractional digits (extra digits are
// truncated). Exponents are refused: the status never uses them.
bool read_fixed(Cursor& c, int decimals, std::int64_t& out) {
  c.skip_space();
  bool negative = false;
  if (c.peek() == '-') {
    negative = true;
    ++c.pos;
  }
  std::int64_t value = 0;
  int digits = 0, fraction = -1;
  constexpr std::int64_t kLimit = INT64_MAX / 10 - 10;
  while (!c.done()) {
    const char ch = c.peek();
    if (ch >= '0' && ch <= '9') {
      if (fraction < 0 || fraction < decimals) {
        if (value > kLimit) return false;
        value = value * 10 + (ch - '0');
        if (fraction >= 0) ++fraction;
      }
      ++digits;
    } else if (ch == '.' && fraction < 0) {
      fraction = 0;
    } else {
      break;
    }
    ++c.pos;
  }
  if (digits == 0) return false;
  for (int f = fraction < 0 ? 0 : fraction; f < decimals; ++f) {
    if (value > kLimit) return false;
    value *= 10;
  }
  out = negative ? -value : value;
  return true;
}

// Skips a value we do not read (string, number, literal); nested values are refused.
bool skip_value(Cursor& c) {
  c.skip_space();
  if (c.eat('"')) return read_string(c, nullptr, 0);
  const std::size_t start = c.pos;
  while (!c.done() && c.peek() != ',' && c.peek() != '}') {
    if (c.peek() == '{' || c.peek() == '[') return false;
    ++c.pos;
  }
  return c.pos > start;
}

}  // namespace

bool parse_flirone_status(std::span<const std::uint8_t> json, FlirOneStatus& out) {
  FlirOneStatus s;
  Cursor c{json};
  if (!c.eat('{')) return false;
  if (c.eat('}')) {
    out = s;
    return true;
  }
  for (;;) {
    if (!c.eat('"')) return false;
    char key[32];
    if (!read_string(c, key, sizeof key)) return false;
    if (!c.eat(':')) return false;
    const std::string_view k(key);
    std::int64_t number = 0;
    if (k == "shutterState" || k == "ffcState") {
      if (!c.eat('"')) return false;
      char* target = k == "shutterState" ? s.shutter_state : s.ffc_state;
      if (!read_string(c, target, FlirOneStatus::kTextCapacity)) return false;
    } else if (k == "shutterTemperature") {
      if (!read_fixed(c, 3, number) || number > INT32_MAX || number < INT32_MIN) return false;
      s.has_shutter_temp = true;
      s.shutter_temp_mk = static_cast<std::int32_t>(number);
    } else if (k == "usbNotifiedTimestamp") {
      if (!read_fixed(c, 9, number)) return false;
      s.has_usb_timestamp = true;
      s.usb_timestamp_ns = number;
    } else if (!skip_value(c)) {
      return false;
    }
    if (c.eat('}')) break;
    if (!c.eat(',')) return false;
  }
  out = s;
  return true;
}

bool flirone_ffc_in_progress(const FlirOneStatus& status) {
  const std::string_view ffc(status.ffc_state);
  return ffc.find("PROGRESS") != std::string_view::npos;
}

}  // namespace bolo::hal
