#pragma once
// Golden vectors: deterministic inputs run through the firmware, hashed, and compared with the
// hashes committed in tests/golden/*.golden. Any change to a rounding, a coefficient or a stage
// shows up as a changed hash on every target.

#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace bolo::test {

inline std::map<std::string, std::string> read_golden(const std::string& path) {
  std::map<std::string, std::string> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string name, hash;
    fields >> name >> hash;
    out[name] = hash;
  }
  return out;
}

inline std::string hex64(std::uint64_t v) {
  char buf[19];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace bolo::test
