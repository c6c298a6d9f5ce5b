#pragma once
// Numeric values on a bench's command line, read whole: atoi/atof would read a typo ("1,5",
// "x") as 0, which for --carry-coring is a valid setting (the paper's full correction) and would
// be timed without a word.

#include <charconv>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace bolo::bench {

// False (after a message naming `tool`, the option and the text on stderr) unless `text` is a
// number of T and nothing else.
template <typename T>
bool parse_number_arg(const char* text, T& out, const char* tool, const char* option) {
  const char* end = text + std::strlen(text);
  T value{};
  const auto [stop, error] = std::from_chars(text, end, value);
  if (error != std::errc{} || stop != end || stop == text) {
    std::fprintf(stderr, "%s: %s: '%s' is not a valid number\n", tool, option, text);
    return false;
  }
  out = value;
  return true;
}

}  // namespace bolo::bench
