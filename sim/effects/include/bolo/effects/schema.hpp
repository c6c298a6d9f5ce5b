#pragma once
// An effect's parameters as `bolo simulate --effect id:key=value,...` takes them: the one
// definition the simulator parses, diagnose reports and writes into simulate.cfg.

#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bolo::effects {

// No default: the effect derives one from the simulation, or needs another key instead.
inline constexpr double kNoDefault = std::numeric_limits<double>::quiet_NaN();

struct Param {
  std::string_view name;
  std::string_view unit;  // "" when dimensionless
  double fallback = kNoDefault;  // used when the spec leaves the key out
  double lo = 0, hi = 0;  // accepted range, inclusive
  bool list = false;      // '/'-separated values
};

// `id:key=value,key=value` with the values as given (already formatted), keys from the schema.
class SpecText {
 public:
  explicit SpecText(std::string_view id) : text_(id) {}
  SpecText& set(const Param& p, const std::string& value) {
    text_ += (first_ ? ":" : ",") + std::string(p.name) + "=" + value;
    first_ = false;
    return *this;
  }
  const std::string& str() const { return text_; }

 private:
  std::string text_;
  bool first_ = true;
};

}  // namespace bolo::effects
