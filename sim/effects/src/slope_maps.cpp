// Per-pixel maps seen as slopes: gain_fpn (a gain per pixel, the residual's slope against the
// level) and tau_spread (a time constant per pixel, the slope against d(baseline)/d(ln tau)).

#include <algorithm>
#include <cmath>

#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "fixed_pattern.hpp"
#include "map_statistics.hpp"
#include "two_frame_derivative.hpp"

namespace bolo::effects {
namespace {

struct GainFpnSchema {
  static constexpr std::string_view id = "gain_fpn";
  static constexpr Param sigma{"sigma", "", 0.01, 0.0, 0.5};
};

struct TauSpreadSchema {
  static constexpr std::string_view id = "tau_spread";
  static constexpr Param sigma{"sigma", "", 0.1, 0.0, 0.5};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// tau_ij = tau (1 + delta_ij), delta ~ N(0, sigma).
class TauSpreadEffect final : public Effect {
  using S = effects::TauSpreadSchema;

 public:
  TauSpreadEffect(const EffectSpec& spec, const SimulationInfo& info) {
    effects::Params p(spec);
    sigma_ = p.number(S::sigma);
    p.finish();
    auto rng = effects::effect_rng(info.seed, id());
    std::normal_distribution<double> n(0.0, sigma_);
    factor_.resize(std::size_t{info.width} * info.height);
    for (auto& f : factor_) f = std::max(0.05, 1.0 + n(rng));
  }
  const char* id() const override { return S::id.data(); }
  void time_constants(const FrameState&, std::span<const double>, std::span<double> tau_h,
                      std::span<double> tau_c) override {
    for (std::size_t p = 0; p < tau_h.size(); ++p) {
      tau_h[p] *= factor_[p];
      tau_c[p] *= factor_[p];
    }
  }
  nlohmann::json parameters() const override { return {{S::sigma.name, sigma_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{"tau_spread_factor", std::vector<float>(factor_.begin(), factor_.end())}};
  }

 private:
  double sigma_;
  std::vector<double> factor_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

// Per-pixel slope of the residual against a regressor image (no intercept):
// gain_fpn against the level, tau_spread against d(baseline)/d(ln tau).
class SlopeMapFit final : public FittedEffect {
 public:
  SlopeMapFit(std::shared_ptr<const std::vector<float>> x, std::vector<float> slope, std::vector<float> intercept,
              std::vector<float> centre, nlohmann::json params, std::string sim, Where where)
      : x_(std::move(x)), slope_(std::move(slope)), intercept_(std::move(intercept)), centre_(std::move(centre)),
        params_(std::move(params)), sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int n, std::span<float> out) const override {
    const float* x = x_->data() + std::size_t(n) * slope_.size();
    for (std::size_t p = 0; p < slope_.size(); ++p) out[p] = intercept_[p] + slope_[p] * (x[p] - centre_[p]);
  }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }

 private:
  std::shared_ptr<const std::vector<float>> x_;
  std::vector<float> slope_, intercept_, centre_;
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

template <bool tau_>
class SlopeMapCandidate final : public Candidate {
 public:
  bool needs_distant_holdout() const override { return true; }
  void release() override { x_.reset(); }
  const char* id() const override { return tau_ ? effects::TauSpreadSchema::id.data() : effects::GainFpnSchema::id.data(); }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    {
      auto x = std::make_shared<std::vector<float>>();
      if (tau_) {
        if (d.has_scene && d.tau_c_s > 0) frame_step_tau_derivative(d, *x);
      } else {
        *x = d.baseline;
      }
      x_ = x;
    }
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene || x_->empty()) return nullptr;
    const std::size_t P = d.shape.pixels();
    PixelSums s = pixel_sums(d, *residual_, train, x_.get());
    std::vector<double> slope(P, 0.0), noise(P, INFINITY), intercept(P, 0.0);
    std::vector<float> centre(P, 0.0f);
    // gain_fpn: y (1 + g) = y + g ybar + g (y - ybar): the slope on the level's change, and the
    // static part g ybar, which pixel by pixel looks like an offset; it is claimed only when the
    // static pattern's spread follows the level (split_by_level; otherwise it is offset_fpn's).
    // tau_spread acts only through the transient.
    LevelSplit split;
    if (!tau_) {
      // The same pixel pattern as offset_fpn's (stripes are effects of their own).
      const TimeAveraged avg = time_averaged(d, s);
      const std::vector<double> rest = avg.pixel_pattern(), &noise_rest = avg.noise;
      const std::vector<double> level2 = squared_levels(s);
      split = split_by_level(rest, noise_rest, level2);
      for (std::size_t p = 0; p < P; ++p) intercept[p] = rest[p] * split.gain_share(level2[p], noise_rest[p]);
      for (std::size_t p = 0; p < P; ++p) {
        if (s.n[p] < 2) continue;
        const double xm = s.x[p] / s.n[p], rm = s.r[p] / s.n[p];
        centre[p] = float(xm);
        s.xr[p] -= s.n[p] * xm * rm;
        s.xx[p] = std::max(0.0, s.xx[p] - s.n[p] * xm * xm);
      }
    }
    double xx_total = 0;
    for (std::size_t p = 0; p < P; ++p) {
      xx_total += s.xx[p];
      if (s.xx[p] > 0) { slope[p] = s.xr[p] / s.xx[p]; noise[p] = s.residual_var / s.xx[p]; }
    }
    if (!(xx_total > 0)) return nullptr;
    // Pixels the regressor barely touches carry no information: leave them at zero.
    const double typical = xx_total / double(P);
    for (std::size_t p = 0; p < P; ++p)
      if (s.xx[p] < 1e-3 * typical) { slope[p] = 0; noise[p] = INFINITY; }
    shrink(slope, noise);
    std::vector<float> map(slope.begin(), slope.end()), icpt(intercept.begin(), intercept.end());
    // The static part's spread measures g directly where it is claimed; the slopes are noisier.
    const double sigma = split.has_gain ? std::sqrt(split.gain_var) : rms(slope);
    nlohmann::json params = {{tau_ ? effects::TauSpreadSchema::sigma.name : effects::GainFpnSchema::sigma.name, sigma}};
    std::string sim = tau_ ? effects::SpecText(effects::TauSpreadSchema::id).set(effects::TauSpreadSchema::sigma, number(sigma)).str()
                           : effects::SpecText(effects::GainFpnSchema::id).set(effects::GainFpnSchema::sigma, number(sigma)).str();
    Where where = whole(d, tau_ ? "per-pixel residual proportional to the input change (each pixel its own tau)"
                                : "per-pixel slope of the residual against the level");
    return std::make_unique<SlopeMapFit>(x_, std::move(map), std::move(icpt), std::move(centre), params, sim, where);
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  std::shared_ptr<const std::vector<float>> x_;
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry gain_fpn() {
  using S = GainFpnSchema;
  return make_entry<sim::FixedPatternEffect<S, sim::Pattern::gain>, diag::SlopeMapCandidate<false>>(S::id, {S::sigma});
}

EffectEntry tau_spread() {
  using S = TauSpreadSchema;
  return make_entry<sim::TauSpreadEffect, diag::SlopeMapCandidate<true>>(S::id, {S::sigma});
}

}  // namespace bolo::effects
