// Readout and response effects: rolling readout, non-linear response, and thermal/optical
// crosstalk between neighbouring pixels.

#include <algorithm>

#include "effects.hpp"
#include "params.hpp"

namespace bolo::sim::effects {
namespace {

// Row k starts its exposure k * line_time_s after row 0.
class RollingReadout final : public Effect {
 public:
  RollingReadout(const EffectSpec& spec, const SimulationInfo& info) {
    Params p(spec);
    line_time_ = p.number("line_time_s", 0.5 / info.fps / std::max(1u, info.height), 0.0, 1.0);
    p.finish();
  }
  const char* id() const override { return "rolling_readout"; }
  double row_delay_s(std::uint32_t row) const override { return row * line_time_; }
  nlohmann::json parameters() const override { return {{"line_time_s", line_time_}}; }

 private:
  double line_time_;
};

// y = y - c (y - y0)^2 around the 300 K level y0.
class Nonlinearity final : public Effect {
 public:
  Nonlinearity(const EffectSpec& spec, const SimulationInfo& info) : y0_(info.reference_level) {
    Params p(spec);
    c_ = p.number("c", 2e-5, -1e-2, 1e-2);
    p.finish();
  }
  const char* id() const override { return "nonlinearity"; }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (double& v : y) v -= c_ * (v - y0_) * (v - y0_);
  }
  nlohmann::json parameters() const override { return {{"c", c_}, {"y0", y0_}}; }

 private:
  double y0_, c_;
};

// y = (1 - eps) y + eps * mean of the 4 neighbours (edges repeat the border pixel).
class Crosstalk final : public Effect {
 public:
  Crosstalk(const EffectSpec& spec, const SimulationInfo& info) : w_(info.width), h_(info.height) {
    Params p(spec);
    eps_ = p.number("epsilon", 0.05, 0.0, 1.0);
    p.finish();
  }
  const char* id() const override { return "crosstalk"; }
  void on_reading(const FrameState&, std::span<double> y) override {
    copy_.assign(y.begin(), y.end());
    auto at = [&](std::int64_t r, std::int64_t c) {
      r = std::clamp<std::int64_t>(r, 0, h_ - 1);
      c = std::clamp<std::int64_t>(c, 0, w_ - 1);
      return copy_[static_cast<std::size_t>(r) * w_ + static_cast<std::size_t>(c)];
    };
    for (std::int64_t r = 0; r < h_; ++r)
      for (std::int64_t c = 0; c < w_; ++c) {
        const double mean4 = 0.25 * (at(r - 1, c) + at(r + 1, c) + at(r, c - 1) + at(r, c + 1));
        y[static_cast<std::size_t>(r) * w_ + static_cast<std::size_t>(c)] =
            (1 - eps_) * at(r, c) + eps_ * mean4;
      }
  }
  nlohmann::json parameters() const override { return {{"epsilon", eps_}}; }

 private:
  std::int64_t w_, h_;
  double eps_;
  std::vector<double> copy_;
};

}  // namespace

std::unique_ptr<Effect> make_rolling_readout(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<RollingReadout>(s, i); }
std::unique_ptr<Effect> make_nonlinearity(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<Nonlinearity>(s, i); }
std::unique_ptr<Effect> make_crosstalk(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<Crosstalk>(s, i); }

}  // namespace bolo::sim::effects
