#pragma once
// The simulator's reading of an effect's spec against its schema (schema.hpp): numbers with
// ranges and defaults, lists, and a check that no unknown key was given. Every error names the
// effect and the key.

#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bolo/effects/schema.hpp"
#include "bolo/sim/effect.hpp"

namespace bolo::effects {

class Params {
 public:
  explicit Params(const sim::EffectSpec& spec) : spec_(spec) {}

  // The schema's default and range.
  double number(const Param& p) { return number(p, p.fallback, p.hi); }
  // A default derived from the simulation (the schema's is NaN).
  double number(const Param& p, double fallback) { return number(p, fallback, p.hi); }
  // An upper bound that depends on the simulation (a count of pixels).
  double number(const Param& p, double fallback, double hi) {
    const std::string key(p.name);
    used_.insert(key);
    const auto it = spec_.params.find(key);
    if (it == spec_.params.end()) return fallback;
    return parse(key, it->second, p.lo, hi);
  }
  std::vector<double> list(const Param& p) {
    const std::string key(p.name);
    used_.insert(key);
    std::vector<double> out;
    const auto it = spec_.params.find(key);
    if (it == spec_.params.end()) return out;
    std::stringstream items(it->second);
    std::string item;
    while (std::getline(items, item, '/')) out.push_back(parse(key, item, p.lo, p.hi));
    return out;
  }
  // Call after reading every key: anything left over is a typo the user should hear about.
  void finish() const {
    for (const auto& [key, value] : spec_.params)
      if (!used_.count(key)) {
        std::string known;
        for (const auto& k : used_) known += (known.empty() ? "" : ", ") + k;
        fail(key, "unknown parameter (" + spec_.id + " takes: " + (known.empty() ? "none" : known) + ")");
      }
  }

 private:
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::invalid_argument("--effect " + spec_.id + ": " + key + ": " + what);
  }
  double parse(const std::string& key, const std::string& text, double lo, double hi) const {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      fail(key, "not a number: '" + text + "'");
    }
    if (used != text.size()) fail(key, "not a number: '" + text + "'");
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream range;
      range << "must be in [" << lo << ", " << hi << "], got " << text;
      fail(key, range.str());
    }
    return v;
  }
  const sim::EffectSpec& spec_;
  std::set<std::string> used_;
};

// An effect's own generator: the simulation seed mixed with the effect id.
inline std::mt19937_64 effect_rng(std::uint64_t seed, const std::string& id) {
  std::uint64_t h = 0xcbf29ce484222325ull ^ seed;
  for (char c : id) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  return std::mt19937_64(h);
}

}  // namespace bolo::effects
