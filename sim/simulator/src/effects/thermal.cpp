// Effects of the pixel's thermal physics: a second, slower thermal path, level-dependent and
// per-pixel time constants.

#include <algorithm>
#include <cmath>

#include "effects.hpp"
#include "params.hpp"

namespace bolo::sim::effects {
namespace {

// x2[n] = a2 x2[n-1] + (1 - a2) w u[n], a2 = exp(-dt / tau2); the reading gains x2.
class ThermalMemory final : public Effect {
 public:
  ThermalMemory(const EffectSpec& spec, const SimulationInfo& info) {
    Params p(spec);
    tau2_ = p.number("tau2_s", 0.2, 1e-4, 100.0);
    weight_ = p.number("weight", 0.03, -1.0, 1.0);
    p.finish();
    state_.assign(std::size_t{info.width} * info.height, 0.0);
  }
  const char* id() const override { return "thermal_memory"; }
  void on_reading(const FrameState& f, std::span<double> y) override {
    const double a2 = std::exp(-f.period_s / tau2_);
    for (std::size_t p = 0; p < y.size(); ++p) {
      state_[p] = a2 * state_[p] + (1.0 - a2) * weight_ * f.mean_input[p];
      y[p] += state_[p];
    }
  }
  nlohmann::json parameters() const override { return {{"tau2_s", tau2_}, {"weight", weight_}}; }

 private:
  double tau2_, weight_;
  std::vector<double> state_;
};

// tau = tau0 (1 + gamma (y - y0)) from the previous reading, y0 the 300 K level.
class TauTemperature final : public Effect {
 public:
  TauTemperature(const EffectSpec& spec, const SimulationInfo& info) : y0_(info.reference_level) {
    Params p(spec);
    gamma_ = p.number("gamma", 2e-5, -1e-2, 1e-2);
    p.finish();
  }
  const char* id() const override { return "tau_temperature"; }
  void time_constants(const FrameState&, std::span<const double> previous, std::span<double> tau_h,
                      std::span<double> tau_c) override {
    if (previous.empty()) return;
    for (std::size_t p = 0; p < tau_h.size(); ++p) {
      const double factor = std::max(0.1, 1.0 + gamma_ * (previous[p] - y0_));
      tau_h[p] *= factor;
      tau_c[p] *= factor;
    }
  }
  nlohmann::json parameters() const override { return {{"gamma", gamma_}, {"y0", y0_}}; }

 private:
  double y0_, gamma_;
};

// tau_ij = tau (1 + delta_ij), delta ~ N(0, sigma).
class TauSpread final : public Effect {
 public:
  TauSpread(const EffectSpec& spec, const SimulationInfo& info) {
    Params p(spec);
    sigma_ = p.number("sigma", 0.1, 0.0, 0.5);
    p.finish();
    auto rng = effect_rng(info.seed, id());
    std::normal_distribution<double> n(0.0, sigma_);
    factor_.resize(std::size_t{info.width} * info.height);
    for (auto& f : factor_) f = std::max(0.05, 1.0 + n(rng));
  }
  const char* id() const override { return "tau_spread"; }
  void time_constants(const FrameState&, std::span<const double>, std::span<double> tau_h,
                      std::span<double> tau_c) override {
    for (std::size_t p = 0; p < tau_h.size(); ++p) {
      tau_h[p] *= factor_[p];
      tau_c[p] *= factor_[p];
    }
  }
  nlohmann::json parameters() const override { return {{"sigma", sigma_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{"tau_spread_factor", std::vector<float>(factor_.begin(), factor_.end())}};
  }

 private:
  double sigma_;
  std::vector<double> factor_;
};

}  // namespace

std::unique_ptr<Effect> make_thermal_memory(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<ThermalMemory>(s, i); }
std::unique_ptr<Effect> make_tau_temperature(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<TauTemperature>(s, i); }
std::unique_ptr<Effect> make_tau_spread(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<TauSpread>(s, i); }

}  // namespace bolo::sim::effects
