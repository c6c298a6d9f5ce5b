#pragma once
// The simulator's half of the fixed-pattern effects (offset_fpn, gain_fpn, column_fpn, row_fpn):
// one map of N(0, sigma) values drawn from the effect's own generator, added per pixel, column or
// row, or multiplying the reading as a gain.

#include <random>
#include <string>
#include <vector>

#include "params.hpp"

namespace bolo::sim {

enum class Pattern { offset, gain, column, row };

// S: the effect's schema (its id and its `sigma`).
template <typename S, Pattern pattern>
class FixedPatternEffect final : public Effect {
 public:
  FixedPatternEffect(const EffectSpec& spec, const SimulationInfo& info) : width_(info.width) {
    effects::Params p(spec);
    sigma_ = p.number(S::sigma);
    p.finish();
    auto rng = effects::effect_rng(info.seed, std::string(S::id));
    std::normal_distribution<double> n(0.0, sigma_);
    const std::size_t count = pattern == Pattern::column ? info.width
                              : pattern == Pattern::row  ? info.height
                                                         : std::size_t{info.width} * info.height;
    values_.resize(count);
    for (auto& v : values_) v = n(rng);
  }
  const char* id() const override { return S::id.data(); }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (std::size_t p = 0; p < y.size(); ++p) {
      switch (pattern) {
        case Pattern::offset: y[p] += values_[p]; break;
        case Pattern::gain: y[p] *= 1.0 + values_[p]; break;
        case Pattern::column: y[p] += values_[p % width_]; break;
        case Pattern::row: y[p] += values_[p / width_]; break;
      }
    }
  }
  nlohmann::json parameters() const override { return {{S::sigma.name, sigma_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{std::string(S::id) + "_values", std::vector<float>(values_.begin(), values_.end())}};
  }

 private:
  std::size_t width_;
  double sigma_;
  std::vector<double> values_;
};

}  // namespace bolo::sim
