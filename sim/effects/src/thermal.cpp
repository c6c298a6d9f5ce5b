// Effects of the pixel's thermal physics: thermal_memory (a second, slower thermal path) and
// tau_temperature (a time constant that follows the pixel's level).

#include <algorithm>
#include <cmath>

#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "params.hpp"
#include "pooled.hpp"
#include "two_frame_derivative.hpp"

namespace bolo::effects {
namespace {

struct ThermalMemorySchema {
  static constexpr std::string_view id = "thermal_memory";
  static constexpr Param tau2_s{"tau2_s", "s", 0.2, 1e-4, 100.0};
  static constexpr Param weight{"weight", "", 0.03, -1.0, 1.0};
};

struct TauTemperatureSchema {
  static constexpr std::string_view id = "tau_temperature";
  static constexpr Param gamma{"gamma", "1/counts", 2e-5, -1e-2, 1e-2};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// x2[n] = a2 x2[n-1] + (1 - a2) w u[n], a2 = exp(-dt / tau2); the reading gains x2.
class ThermalMemoryEffect final : public Effect {
  using S = effects::ThermalMemorySchema;

 public:
  ThermalMemoryEffect(const EffectSpec& spec, const SimulationInfo& info) {
    effects::Params p(spec);
    tau2_ = p.number(S::tau2_s);
    weight_ = p.number(S::weight);
    p.finish();
    state_.assign(std::size_t{info.width} * info.height, 0.0);
  }
  const char* id() const override { return S::id.data(); }
  void on_reading(const FrameState& f, std::span<double> y) override {
    const double a2 = std::exp(-f.period_s / tau2_);
    for (std::size_t p = 0; p < y.size(); ++p) {
      state_[p] = a2 * state_[p] + (1.0 - a2) * weight_ * f.mean_input[p];
      y[p] += state_[p];
    }
  }
  nlohmann::json parameters() const override { return {{S::tau2_s.name, tau2_}, {S::weight.name, weight_}}; }

 private:
  double tau2_, weight_;
  std::vector<double> state_;
};

// tau = tau0 (1 + gamma (y - y0)) from the previous reading, y0 the 300 K level.
class TauTemperatureEffect final : public Effect {
  using S = effects::TauTemperatureSchema;

 public:
  TauTemperatureEffect(const EffectSpec& spec, const SimulationInfo& info) : y0_(info.reference_level) {
    effects::Params p(spec);
    gamma_ = p.number(S::gamma);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void time_constants(const FrameState&, std::span<const double> previous, std::span<double> tau_h,
                      std::span<double> tau_c) override {
    if (previous.empty()) return;
    for (std::size_t p = 0; p < tau_h.size(); ++p) {
      const double factor = std::max(0.1, 1.0 + gamma_ * (previous[p] - y0_));
      tau_h[p] *= factor;
      tau_c[p] *= factor;
    }
  }
  nlohmann::json parameters() const override { return {{S::gamma.name, gamma_}, {"y0", y0_}}; }

 private:
  double y0_, gamma_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

// A second, slower thermal path: the residual follows a slow low-pass of the input minus the
// input itself (its steady-state share is in the baseline gain).
class ThermalMemoryCandidate final : public PooledLinear {
  using S = effects::ThermalMemorySchema;

 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 2; }

 protected:
  // 12 time constants, each with the slow path settled on the first frame or starting cold.
  int alternatives() const override { return 24; }
  bool cold(int alt) const { return alt >= 12; }
  double tau2(int alt) const {
    alt %= 12;
    const double dt = 1.0 / data_->fps, span = data_->t_s.back() - data_->t_s.front();
    const double lo = std::max(1.5 * dt, 0.02), hi = std::max(lo * 2, std::min(10.0, 0.5 * span));
    return lo * std::pow(hi / lo, alt / 11.0);
  }
  bool regressors(int alt, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene) return false;  // a static background has no transients
    const std::size_t P = d.shape.pixels();
    X.assign(1, std::vector<float>(d.shape.size()));
    std::vector<float> state(d.frame(d.baseline, 0), d.frame(d.baseline, 0) + P);
    if (cold(alt)) std::fill(state.begin(), state.end(), 0.0f);
    for (int n = 0; n < d.shape.n; ++n) {
      const double dt = n == 0 ? 1.0 / d.fps : d.t_s[n] - d.t_s[n - 1];
      const float a = static_cast<float>(std::exp(-dt / tau2(alt)));
      const float* b = d.frame(d.baseline, n);
      float* x = X[0].data() + std::size_t(n) * P;
      for (std::size_t p = 0; p < P; ++p) {
        state[p] = a * state[p] + (1 - a) * b[p];
        x[p] = state[p] - b[p];
      }
    }
    return true;
  }
  nlohmann::json params_of(int alt, const Eigen::VectorXd& beta) const override {
    return {{S::tau2_s.name, tau2(alt)}, {S::weight.name, beta[0]}, {"start", cold(alt) ? "cold" : "settled"}};
  }
  // A substrate path holds a small share of the signal.
  bool physical(int, const Eigen::VectorXd& beta) const override { return std::fabs(beta[0]) < 0.3; }
  std::string simulator_text(int alt, const Eigen::VectorXd& beta) const override {
    return effects::SpecText(S::id).set(S::tau2_s, number(tau2(alt))).set(S::weight, number(beta[0])).str();
  }
  std::string summary() const override { return "tails after changes of the input, beyond one frame"; }
};

class TauTemperatureCandidate final : public PooledLinear {
  using S = effects::TauTemperatureSchema;

 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }

 protected:
  // The camera reads its input in steady state at every level: only the transient depends on
  // gamma. A steady state that bends with the level is nonlinearity's (one candidate per idea;
  // with it here too, this candidate took nonlinearity's recordings).
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene || !(d.tau_c_s > 0)) return false;
    X.assign(1, {});
    const double tau_h = d.tau_h_s > 0 ? d.tau_h_s : d.tau_c_s;  // the baseline's own assumption
    level_tau_derivative(d, d.tau_c_s, tau_h, d.level_mid, X[0]);
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override {
    return {{S::gamma.name, beta[0]}, {"y0", data_->level_mid}};
  }
  // tau stays positive over the levels of the recording: |gamma| x (level range) well below 1.
  bool physical(int, const Eigen::VectorXd& beta) const override {
    const auto [lo, hi] = std::minmax_element(data_->baseline.begin(), data_->baseline.end());
    return std::fabs(beta[0]) * (*hi - *lo) < 0.5;
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return effects::SpecText(S::id).set(S::gamma, number(beta[0])).str();
  }
  std::string summary() const override { return "transients whose time constant grows with the pixel's level"; }
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry thermal_memory() {
  using S = ThermalMemorySchema;
  return make_entry<sim::ThermalMemoryEffect, diag::ThermalMemoryCandidate>(S::id, {S::tau2_s, S::weight});
}

EffectEntry tau_temperature() {
  using S = TauTemperatureSchema;
  return make_entry<sim::TauTemperatureEffect, diag::TauTemperatureCandidate>(S::id, {S::gamma});
}

}  // namespace bolo::effects
