#include <stdexcept>

#include "bolo/sim/effect.hpp"

namespace bolo::sim {

EffectSpec parse_effect(const std::string& text) {
  EffectSpec spec;
  const auto colon = text.find(':');
  spec.id = text.substr(0, colon);
  if (spec.id.empty()) throw std::invalid_argument("--effect '" + text + "': no effect id");
  if (colon == std::string::npos) return spec;
  std::string rest = text.substr(colon + 1);
  std::size_t start = 0;
  while (start <= rest.size()) {
    const auto comma = rest.find(',', start);
    const std::string item = rest.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto eq = item.find('=');
    if (item.empty() || eq == std::string::npos || eq == 0 || eq + 1 == item.size())
      throw std::invalid_argument("--effect '" + text + "': expected key=value, got '" + item + "'");
    const std::string key = item.substr(0, eq);
    if (spec.params.count(key))
      throw std::invalid_argument("--effect '" + text + "': " + key + " given twice");
    spec.params[key] = item.substr(eq + 1);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return spec;
}

}  // namespace bolo::sim
