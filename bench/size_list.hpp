#pragma once
// Frame sizes on a bench's command line: "WxH[,WxH...]" (bolo-bench, bolo-vo-bench).

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace bolo::bench {

struct Size {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::string label() const { return std::to_string(width) + "x" + std::to_string(height); }
};

inline bool parse_size(std::string_view text, Size& out) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string_view::npos || x == 0 || x + 1 >= text.size()) return false;
  auto parse_dim = [](std::string_view s, std::uint32_t& v) {
    if (s.empty() || s.size() > 5) return false;
    std::uint32_t n = 0;
    for (char c : s) {
      if (c < '0' || c > '9') return false;
      n = n * 10 + static_cast<std::uint32_t>(c - '0');
    }
    if (n == 0 || n > 16384) return false;
    v = n;
    return true;
  };
  // At most 2^26 pixels (128 MiB a frame): the benches keep several frames plus tables.
  return parse_dim(text.substr(0, x), out.width) && parse_dim(text.substr(x + 1), out.height) &&
         std::uint64_t{out.width} * out.height <= (std::uint64_t{1} << 26);
}

// The sizes of a comma-separated list, each once, in order. False (after a message naming `tool`
// and the bad item on stderr) for a malformed or empty list.
inline bool parse_size_list(std::string_view list, std::vector<Size>& out, const char* tool) {
  out.clear();
  while (!list.empty()) {
    const std::size_t comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    Size s;
    if (!parse_size(item, s)) {
      std::fprintf(stderr, "%s: bad size '%.*s' in --sizes (want WxH, 1..16384 each, at most 2^26 pixels)\n", tool,
                   static_cast<int>(item.size()), item.data());
      return false;
    }
    const bool seen = std::any_of(out.begin(), out.end(), [&](const Size& t) {
      return t.width == s.width && t.height == s.height;
    });
    if (!seen) out.push_back(s);  // a size twice would be measured (and a JSON key written) twice
    list = comma == std::string_view::npos ? std::string_view{} : list.substr(comma + 1);
  }
  if (out.empty()) {
    std::fprintf(stderr, "%s: --sizes is empty\n", tool);
    return false;
  }
  return true;
}

}  // namespace bolo::bench
