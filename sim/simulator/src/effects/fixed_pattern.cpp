// Fixed-pattern effects: per-pixel offset and gain, column and row offsets, and the smooth
// shading field from lens and housing.

#include <cmath>

#include "effects.hpp"
#include "params.hpp"

namespace bolo::sim::effects {
namespace {

enum class Pattern { offset, gain, column, row };

class FixedPattern final : public Effect {
 public:
  FixedPattern(const EffectSpec& spec, const SimulationInfo& info, Pattern pattern, const char* name)
      : pattern_(pattern), name_(name), width_(info.width) {
    Params p(spec);
    sigma_ = p.number("sigma", pattern == Pattern::gain ? 0.01 : 5.0, 0.0, pattern == Pattern::gain ? 0.5 : 1e4);
    p.finish();
    auto rng = effect_rng(info.seed, name_);
    std::normal_distribution<double> n(0.0, sigma_);
    const std::size_t count = pattern == Pattern::column ? info.width
                              : pattern == Pattern::row  ? info.height
                                                         : std::size_t{info.width} * info.height;
    values_.resize(count);
    for (auto& v : values_) v = n(rng);
  }
  const char* id() const override { return name_; }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (std::size_t p = 0; p < y.size(); ++p) {
      switch (pattern_) {
        case Pattern::offset: y[p] += values_[p]; break;
        case Pattern::gain: y[p] *= 1.0 + values_[p]; break;
        case Pattern::column: y[p] += values_[p % width_]; break;
        case Pattern::row: y[p] += values_[p / width_]; break;
      }
    }
  }
  nlohmann::json parameters() const override { return {{"sigma", sigma_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{std::string(name_) + "_values", std::vector<float>(values_.begin(), values_.end())}};
  }

 private:
  Pattern pattern_;
  const char* name_;
  std::size_t width_;
  double sigma_;
  std::vector<double> values_;
};

// y += amplitude * (xn^2 + yn^2) / 2, xn and yn in [-1, 1]: amplitude at the corners, 0 at the
// centre. Not reset by shutter events (it comes from in front of the shutter).
class Shading final : public Effect {
 public:
  Shading(const EffectSpec& spec, const SimulationInfo& info) : w_(info.width), h_(info.height) {
    Params p(spec);
    amplitude_ = p.number("amplitude", 30.0, -1e4, 1e4);
    p.finish();
  }
  const char* id() const override { return "shading"; }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (std::uint32_t r = 0; r < h_; ++r)
      for (std::uint32_t c = 0; c < w_; ++c) y[std::size_t{r} * w_ + c] += field(r, c);
  }
  nlohmann::json parameters() const override { return {{"amplitude", amplitude_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    std::vector<float> m(std::size_t{w_} * h_);
    for (std::uint32_t r = 0; r < h_; ++r)
      for (std::uint32_t c = 0; c < w_; ++c) m[std::size_t{r} * w_ + c] = static_cast<float>(field(r, c));
    return {{"shading_field", m}};
  }

 private:
  double field(std::uint32_t r, std::uint32_t c) const {
    const double xn = w_ > 1 ? 2.0 * c / (w_ - 1) - 1.0 : 0.0;
    const double yn = h_ > 1 ? 2.0 * r / (h_ - 1) - 1.0 : 0.0;
    return amplitude_ * (xn * xn + yn * yn) / 2.0;
  }
  std::uint32_t w_, h_;
  double amplitude_;
};

}  // namespace

std::unique_ptr<Effect> make_offset_fpn(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FixedPattern>(s, i, Pattern::offset, "offset_fpn"); }
std::unique_ptr<Effect> make_gain_fpn(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FixedPattern>(s, i, Pattern::gain, "gain_fpn"); }
std::unique_ptr<Effect> make_column_fpn(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FixedPattern>(s, i, Pattern::column, "column_fpn"); }
std::unique_ptr<Effect> make_row_fpn(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FixedPattern>(s, i, Pattern::row, "row_fpn"); }
std::unique_ptr<Effect> make_shading(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<Shading>(s, i); }

}  // namespace bolo::sim::effects
