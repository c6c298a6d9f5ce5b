#pragma once
// Numeric values on a bench's command line (bolo-bench, bolo-vo-bench), read whole and checked
// against their range: atoi/atof would read a typo ("1,5", "x") as 0, which for
// bolo-vo-bench --carry-coring is a valid setting (the paper's full correction) and would be timed
// without a word.

#include <charconv>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace bolo::bench {

// False (after "TOOL: OPTION wants WANTS, got 'TEXT'" on stderr) unless `text` is a number of T
// and nothing else, within [lo, hi] (exclusive of lo when `lo_open`).
template <typename T>
bool parse_number_arg(const char* text, T& out, T lo, T hi, const char* tool, const char* option, const char* wants,
                      bool lo_open = false) {
  const char* end = text + std::strlen(text);
  T value{};
  const auto [stop, error] = std::from_chars(text, end, value);
  const bool in_range = (lo_open ? value > lo : value >= lo) && value <= hi;
  if (error != std::errc{} || stop != end || stop == text || !in_range) {
    std::fprintf(stderr, "%s: %s wants %s, got '%s'\n", tool, option, wants, text);
    return false;
  }
  out = value;
  return true;
}

}  // namespace bolo::bench
