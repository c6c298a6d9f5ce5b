// Effects of the pixel's thermal physics: thermal_memory (a second, slower thermal path) and
// tau_temperature (a time constant that follows the pixel's level).

#include <algorithm>
#include <cmath>
#include <limits>

#include "bolo/diagnose/far_off_pixels.hpp"
#include "bolo/effects/scene_flow.hpp"
#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "four_neighbours.hpp"
#include "params.hpp"
#include "pooled.hpp"
#include "shared_coefficient_z.hpp"
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

// How far a time constant that follows the level stands out of its sampling error: the residual's
// regression on d(output)/d(gamma) (level_tau_derivative) beside the terms each unit of
// unit_estimates fits for itself: a uniform tau (transient_tau_derivative), a common delay and one
// that grows with the row (the baseline's central frame difference and the delay response along
// the flow, each also times the row), the four-neighbour blur, the level and its square, and the
// motion term (within_exposure). A misjudged transient, motion term or readout scales with the
// step whatever its level, and a reading that bends with the level (nonlinearity) changes as a
// pixel steps from one level to another; the transient's delay growing with the level is what is
// left. It must hold in the top and the bottom half of the frame alike, with one sign (either is
// physical): the smaller of the halves' |z| times sqrt(2). NaN under 8 blocks.
double level_tau_z(const DiagnoseData& d, const std::vector<float>& residual, const std::vector<float>& per_gamma,
                   const std::vector<float>& per_ln_tau, const std::vector<float>& response,
                   const std::vector<std::uint8_t>& far) {
  const int W = d.shape.width, H = d.shape.height, N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  // Each pixel's mean out of the residual and of the level terms: a standing offset (a fixed
  // pattern the baseline lacks) makes no transient, and a reading that bends with the level
  // changes at a pixel only as its level does.
  const double scale = std::max(1.0, std::fabs(d.level_mid));
  auto level_of = [&](std::size_t i) { return (double(d.baseline[i]) - d.level_mid) / scale; };
  std::vector<double> count(P, 0.0), mean_r(P, 0.0), mean_q(P, 0.0), mean_q2(P, 0.0);
  for (std::size_t i = 0; i < residual.size(); ++i)
    if (d.valid[i]) {
      const std::size_t p = i % P;
      const double q = level_of(i);
      count[p] += 1, mean_r[p] += residual[i], mean_q[p] += q, mean_q2[p] += q * q;
    }
  for (std::size_t p = 0; p < P; ++p)
    if (count[p] > 0) mean_r[p] /= count[p], mean_q[p] /= count[p], mean_q2[p] /= count[p];
  std::vector<float> r(residual.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = residual[i] - float(mean_r[i % P]);
  const bool motion = d.within_exposure.size() == d.shape.size(), flow = response.size() == d.shape.size();
  using Terms = Eigen::Matrix<double, 10, 1>;
  const UnitEstimates u = unit_estimates<10>(d, r, far, [&](int n, int y, int c, std::size_t p, UnitRows rows, Terms& z) {
    const float* level = d.frame(d.baseline, n);
    const float g = d.frame(per_gamma, n)[p];
    if (g == 0.0f || n == 0 || n + 1 >= N) return false;
    const std::size_t i = std::size_t(n) * P + p;
    const double rate = 0.5 * (double(d.frame(d.baseline, n + 1)[p]) - d.frame(d.baseline, n - 1)[p]);
    const double row = y - 0.5 * (rows.first + rows.last - 1), q = level_of(i);
    const double along_flow = flow ? double(response[i]) : 0.0;
    z << g, per_ln_tau[i], rate, rate * row, along_flow, along_flow * row,
        effects::mean_of_four_neighbours(level, W, H, y, c) - level[p], q - mean_q[p], q * q - mean_q2[p],
        motion ? double(d.within_exposure[i]) : 0.0;
    return true;
  });
  const double top = shared_coefficient_z(u, 0), bottom = shared_coefficient_z(u, 1);
  if (!std::isfinite(top) || !std::isfinite(bottom)) return std::numeric_limits<double>::quiet_NaN();
  return top * bottom > 0 ? std::sqrt(2.0) * std::min(std::fabs(top), std::fabs(bottom)) : 0.0;
}

// The level's signature needs the moving edges modelled: where the baseline masks them as its
// misses (more than 1 % of the pixel-frames), the transients beside the masks carry the misses'
// tails, which follow the moving objects' levels (bolo's demo nulls with 4 sub-steps read z 25-39).
bool motion_modelled(const DiagnoseData& d) {
  constexpr double kMaxMaskedShare = 0.01;
  std::size_t masked = 0;
  const bool clipping = d.unclipped.size() == d.valid.size();
  for (std::size_t i = 0; i < d.valid.size(); ++i) masked += !d.valid[i] && (!clipping || d.unclipped[i]);
  return double(masked) <= kMaxMaskedShare * double(std::max<std::size_t>(1, d.valid.size()));
}

// Judged by its signature (level_tau_z) rather than by the share of the mismatch it explains: a
// uniform tau takes most of what this effect adds, and the motion term's misses at moving edges
// outweigh what is left. Where the edges are masked (motion_modelled), by the floor and the share.
class TauTemperatureCandidate final : public PooledLinear {
  using S = effects::TauTemperatureSchema;

 public:
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    per_gamma_.clear();
    signature_z_ = std::numeric_limits<double>::quiet_NaN();
    if (d.has_scene && d.tau_c_s > 0) {
      const double tau_h = d.tau_h_s > 0 ? d.tau_h_s : d.tau_c_s;  // the baseline's own assumption
      level_tau_derivative(d, d.tau_c_s, tau_h, d.level_mid, per_gamma_);
    }
    PooledLinear::prepare(d, r);
    if (!per_gamma_.empty() && motion_modelled(d)) {
      std::vector<float> response;
      delay_response(d, d.tau_c_s, response);
      signature_z_ = level_tau_z(d, r, per_gamma_, tau_nuisance(), response, far_off_pixels(d, [&](std::size_t i) { return r[i]; }));
    }
  }
  void release() override {
    PooledLinear::release();
    per_gamma_ = {};
  }
  double signature_z() const override { return signature_z_; }
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }

 protected:
  // The camera reads its input in steady state at every level: only the transient depends on
  // gamma. A steady state that bends with the level is nonlinearity's (one candidate per idea;
  // with it here too, this candidate took nonlinearity's recordings).
  bool regressors(int, Regressors& X) const override {
    if (per_gamma_.empty()) return false;
    X.assign(1, per_gamma_);
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

 private:
  double signature_z_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<float> per_gamma_;  // level_tau_derivative for this round (empty: none)
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
