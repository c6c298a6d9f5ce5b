#pragma once
// The HIL programs' option values: a whole non-negative number, or an error naming the option.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace bolo::hil {

inline std::uint64_t whole_number(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  std::uint64_t v = 0;
  try {
    v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || text[0] == '-')
    throw std::runtime_error(option + ": '" + text + "' is not a whole number");
  return v;
}

}  // namespace bolo::hil
