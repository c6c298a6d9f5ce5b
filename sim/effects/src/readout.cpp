// Readout and response effects: rolling readout, non-linear response, and thermal/optical
// crosstalk between neighbouring pixels.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include <Eigen/Dense>

#include "bolo/diagnose/far_off_pixels.hpp"
#include "bolo/effects/scene_flow.hpp"
#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "params.hpp"
#include "four_neighbours.hpp"
#include "pooled.hpp"
#include "shared_coefficient_z.hpp"

namespace bolo::effects {
namespace {

struct RollingReadoutSchema {
  static constexpr std::string_view id = "rolling_readout";
  // Default: the rows spread over half a frame period.
  static constexpr Param line_time_s{"line_time_s", "s", kNoDefault, 0.0, 1.0};
};

struct NonlinearitySchema {
  static constexpr std::string_view id = "nonlinearity";
  static constexpr Param c{"c", "1/counts", 2e-5, -1e-2, 1e-2};
};

struct CrosstalkSchema {
  static constexpr std::string_view id = "crosstalk";
  static constexpr Param epsilon{"epsilon", "", 0.05, 0.0, 1.0};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// Row k starts its exposure k * line_time_s after row 0.
class RollingReadoutEffect final : public Effect {
  using S = effects::RollingReadoutSchema;

 public:
  RollingReadoutEffect(const EffectSpec& spec, const SimulationInfo& info) {
    effects::Params p(spec);
    line_time_ = p.number(S::line_time_s, 0.5 / info.fps / std::max(1u, info.height));
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  double row_delay_s(std::uint32_t row) const override { return row * line_time_; }
  nlohmann::json parameters() const override { return {{S::line_time_s.name, line_time_}}; }

 private:
  double line_time_;
};

// y = y - c (y - y0)^2 around the 300 K level y0.
class NonlinearityEffect final : public Effect {
  using S = effects::NonlinearitySchema;

 public:
  NonlinearityEffect(const EffectSpec& spec, const SimulationInfo& info) : y0_(info.reference_level) {
    effects::Params p(spec);
    c_ = p.number(S::c);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (double& v : y) v -= c_ * (v - y0_) * (v - y0_);
  }
  nlohmann::json parameters() const override { return {{S::c.name, c_}, {"y0", y0_}}; }

 private:
  double y0_, c_;
};

// y = (1 - eps) y + eps * mean of the 4 neighbours (edges repeat the border pixel).
class CrosstalkEffect final : public Effect {
  using S = effects::CrosstalkSchema;

 public:
  CrosstalkEffect(const EffectSpec& spec, const SimulationInfo& info) : w_(info.width), h_(info.height) {
    effects::Params p(spec);
    eps_ = p.number(S::epsilon);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void on_reading(const FrameState&, std::span<double> y) override {
    copy_.assign(y.begin(), y.end());
    for (std::int64_t r = 0; r < h_; ++r)
      for (std::int64_t c = 0; c < w_; ++c) {
        const std::size_t i = static_cast<std::size_t>(r * w_ + c);
        y[i] = (1 - eps_) * copy_[i] + eps_ * effects::mean_of_four_neighbours(copy_.data(), w_, h_, r, c);
      }
  }
  nlohmann::json parameters() const override { return {{S::epsilon.name, eps_}}; }

 private:
  std::int64_t w_, h_;
  double eps_;
  std::vector<double> copy_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

// How far a delay that grows with the row stands out of its sampling error: the residual's
// regression on the delay response (delay_response, the input's change over one exposure along
// the flow) times the row, beside the response itself, the response times the pixel's level and
// the baseline's four-neighbour blur. Each unit, the top or bottom half of the frame over a block
// of 10 frames, has its own coefficients for those; the row's coefficient is shared, z against the
// units' spread. A common delay (a timing shift, a time constant misjudged on the moving edges) is
// the same on every row, a time constant that follows the level (tau_temperature) delays the hot
// and cold objects wherever they sit, crosstalk blurs the edges whichever way they move, and the
// motion term's misses where an object enters or stands at one side of the frame differ between
// the halves, not within them; the readout's shear grows within each. NaN under 8 blocks or
// without a flow.
double row_delay_slope_z(const DiagnoseData& d, const std::vector<float>& r, const std::vector<float>& response,
                         const std::vector<std::uint8_t>& far) {
  if (response.empty()) return std::numeric_limits<double>::quiet_NaN();
  const int W = d.shape.width, H = d.shape.height;
  return shared_coefficient_z(unit_estimates<4>(d, r, far, [&](int n, int y, int c, std::size_t p, UnitRows rows, Eigen::Vector4d& z) {
    const float *x = d.frame(response, n), *level = d.frame(d.baseline, n);
    if (x[p] == 0.0f) return false;
    const double blur = effects::mean_of_four_neighbours(level, W, H, y, c) - level[p];
    z << x[p] * (y - 0.5 * (rows.first + rows.last - 1)), x[p], x[p] * (double(level[p]) - d.level_mid), blur;
    return true;
  }));
}

// Row k is read k * line_time later: it sees the input a little later, and the residual is that
// delay times the input's rate of change, carried on through the two-frame response. Three
// estimates of the rate, scored as alternatives: the baseline's central and forward frame
// differences (right for motion that is slow against the edges' widths; rows counted from the
// middle, as the rows' common delay is then the baseline's timing shift), and the input's change
// over one exposure along the scene's own motion, divided by the exposure (d/d(delay) of an
// exposure-long average; rows counted from row 0). A frame difference spreads a fast sharp edge's
// change over its whole frame-to-frame sweep; the exposure's share of the sweep sits where the
// delay acts. Judged by its shear (row_delay_slope_z, signature_z) rather than by the share of
// the mismatch it explains, which at moving edges is mostly the motion term's.
class RollingReadoutCandidate final : public PooledLinear {
  using S = effects::RollingReadoutSchema;

 public:
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    // The delay response is one of the regressors and the shear's too: found once per round.
    response_.clear();
    if (d.has_scene) delay_response(d, d.tau_c_s, response_);
    PooledLinear::prepare(d, r);
    signature_z_ = d.has_scene ? row_delay_slope_z(d, r, response_, far_off_pixels(d, [&](std::size_t i) { return r[i]; }))
                               : std::numeric_limits<double>::quiet_NaN();
  }
  void release() override {
    PooledLinear::release();
    response_ = {};
  }
  double signature_z() const override { return signature_z_; }
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }

 protected:
  int alternatives() const override { return 3; }
  // The second regressor lets the baseline's timing shift move with the effect (its share of
  // the rows' common delay), as refits_tau lets tau move: d(baseline)/d(shift) is the baseline's
  // central frame difference. Not counted as a parameter, like tau.
  int regressor_count() const override { return 2; }
  bool regressors(int alt, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene || d.shape.n < 3) return false;
    X.assign(2, std::vector<float>(d.shape.size(), 0.0f));
    const std::size_t P = d.shape.pixels();
    for (int n = 1; n + 1 < d.shape.n; ++n) {
      const float *next = d.frame(d.baseline, n + 1), *prev = d.frame(d.baseline, n - 1);
      float* out = X[1].data() + std::size_t(n) * P;
      for (std::size_t p = 0; p < P; ++p) out[p] = 0.5f * (next[p] - prev[p]);
    }
    return alt < 2 ? frame_difference_rate(alt == 1, X[0]) : exposure_rate_along_flow(X[0]);
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{S::line_time_s.name, beta[0]}}; }
  // Rows are read after one another: a positive line time, all rows within one frame period.
  bool physical(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 && beta[0] * data_->shape.height < 1.0 / data_->fps;
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 ? effects::SpecText(S::id).set(S::line_time_s, number(beta[0])).str() : "";
  }
  std::string summary() const override { return "residual proportional to row index x temporal derivative (moving edges sheared)"; }

 private:
  double signature_z_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<float> response_;  // delay_response for this round (empty: none)
  double row_from_middle(std::size_t p) const {
    return double(p / std::size_t(data_->shape.width)) - 0.5 * (data_->shape.height - 1);
  }

  bool frame_difference_rate(bool forward, std::vector<float>& x) const {
    const DiagnoseData& d = *data_;
    const std::size_t P = d.shape.pixels();
    for (int n = 0; n < d.shape.n; ++n) {
      const int a = forward ? n : std::max(0, n - 1), b = std::min(d.shape.n - 1, n + 1);
      if (a == b) continue;
      const double dt = d.t_s[b] - d.t_s[a];
      const float *fa = d.frame(d.baseline, a), *fb = d.frame(d.baseline, b);
      float* out = x.data() + std::size_t(n) * P;
      for (std::size_t p = 0; p < P; ++p) out[p] = static_cast<float>(row_from_middle(p) * (fb[p] - fa[p]) / dt);
    }
    return true;
  }

  bool exposure_rate_along_flow(std::vector<float>& x) const {
    const DiagnoseData& d = *data_;
    const std::vector<float>& response = response_;
    if (response.empty()) return false;
    const std::size_t P = d.shape.pixels();
    // Here the common delay is the effect's too: the baseline's timing shift, on frame differences,
    // cannot hold a delay of edges that cross pixels within an exposure.
    const int W = d.shape.width;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(d.gain * double((i % P) / W) * response[i]);
    return true;
  }
};

class CrosstalkCandidate final : public PooledLinear {
  using S = effects::CrosstalkSchema;

 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }

 protected:
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene) return false;  // the static background already holds the blur
    const int H = d.shape.height, W = d.shape.width;
    const std::size_t P = d.shape.pixels();
    X.assign(1, std::vector<float>(d.shape.size()));
    for (int n = 0; n < d.shape.n; ++n) {
      const float* b = d.frame(d.baseline, n);
      float* x = X[0].data() + std::size_t(n) * P;
      for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
          x[r * W + c] = effects::mean_of_four_neighbours(b, W, H, r, c) - b[r * W + c];
    }
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{S::epsilon.name, beta[0]}}; }
  bool physical(int, const Eigen::VectorXd& beta) const override { return beta[0] > 0 && beta[0] < 0.5; }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 ? effects::SpecText(S::id).set(S::epsilon, number(beta[0])).str() : "";
  }
  std::string summary() const override { return "residual proportional to the Laplacian of the image (edges and hot spots)"; }
};

class NonlinearityCandidate final : public PooledLinear {
  using S = effects::NonlinearitySchema;

 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }

 protected:
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene) return false;  // steady state is in the background itself
    const double y0 = d.level_mid;
    X.assign(1, std::vector<float>(d.shape.size()));
    // -(B - y0)^2 with its projection on [1, B] removed: the baseline fit already took those.
    double n = 0, sb = 0, sbb = 0, sq = 0, sbq = 0;
    for (std::size_t i = 0; i < X[0].size(); ++i) {
      const double b = d.baseline[i] - y0, q = -b * b;
      if (d.valid[i]) { n += 1; sb += b; sbb += b * b; sq += q; sbq += b * q; }
      X[0][i] = static_cast<float>(q);
    }
    const double vb = sbb - sb * sb / n;
    if (!(vb > 0)) return false;
    const double slope = (sbq - sb * sq / n) / vb, icpt = (sq - slope * sb) / n;
    for (std::size_t i = 0; i < X[0].size(); ++i) X[0][i] -= static_cast<float>(icpt + slope * (d.baseline[i] - y0));
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override {
    return {{S::c.name, beta[0]}, {"y0", data_->level_mid}};
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return effects::SpecText(S::id).set(S::c, number(beta[0])).str();
  }
  std::string summary() const override { return "residual curved against the simulated level"; }
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry rolling_readout() {
  using S = RollingReadoutSchema;
  return make_entry<sim::RollingReadoutEffect, diag::RollingReadoutCandidate>(S::id, {S::line_time_s});
}

EffectEntry nonlinearity() {
  using S = NonlinearitySchema;
  return make_entry<sim::NonlinearityEffect, diag::NonlinearityCandidate>(S::id, {S::c});
}

EffectEntry crosstalk() {
  using S = CrosstalkSchema;
  return make_entry<sim::CrosstalkEffect, diag::CrosstalkCandidate>(S::id, {S::epsilon});
}

}  // namespace bolo::effects
