// Effects that act on transients and spatial structure of the image, pooled over all pixels:
// thermal_memory, tau_temperature, rolling_readout, crosstalk, nonlinearity, temporal_filter.

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dynamic_effects.hpp"
#include "stats.hpp"
#include "pooled.hpp"
#include "scene_flow.hpp"

namespace bolo::diag {
namespace {

// A second, slower thermal path: the residual follows a slow low-pass of the input minus the
// input itself (its steady-state share is in the baseline gain).
class ThermalMemory final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "thermal_memory"; }
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
    return {{"tau2_s", tau2(alt)}, {"weight", beta[0]}, {"start", cold(alt) ? "cold" : "settled"}};
  }
  // A substrate path holds a small share of the signal.
  bool physical(int, const Eigen::VectorXd& beta) const override { return std::fabs(beta[0]) < 0.3; }
  std::string simulator_text(int alt, const Eigen::VectorXd& beta) const override {
    return "thermal_memory:tau2_s=" + number(tau2(alt)) + ",weight=" + number(beta[0]);
  }
  std::string summary() const override { return "tails after changes of the input, beyond one frame"; }
};

// Two-frame sensitivity: d(output)/d(parameter) propagated through the two-frame recursion.
// dc_n/dp and dk_n/dp come from `scale(n, p)` = d ln(tau)/dp at that pixel-frame.
template <typename Scale>
void two_frame_derivative(const DiagnoseData& d, double tau_c, double gain, Scale scale, std::vector<float>& out) {
  const std::size_t P = d.shape.pixels();
  out.assign(d.shape.size(), 0.0f);
  std::vector<double> s(P), ds(P, 0.0);
  const float* b0 = d.frame(d.baseline, 0);
  for (std::size_t p = 0; p < P; ++p) s[p] = b0[p];
  for (int n = 1; n < d.shape.n; ++n) {
    const double c = std::exp(-d.readout_s[n - 1] / tau_c);
    const double dc_dlntau = c * d.readout_s[n - 1] / tau_c;
    const float* b = d.frame(d.baseline, n);
    const float* bp = d.frame(d.baseline, n - 1);
    float* o = out.data() + std::size_t(n) * P;
    for (std::size_t p = 0; p < P; ++p) {
      // s_n = c s_{n-1} + (1 - c) u_n, with u_n recovered from the baseline (units of the recording).
      const double u = (b[p] - c * bp[p]) / (1 - c);
      ds[p] = dc_dlntau * scale(n, p) * (bp[p] - u) + c * ds[p];
      o[p] = static_cast<float>(ds[p]);
    }
  }
  (void)gain;
}

class TauTemperature final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "tau_temperature"; }
  int parameter_count() const override { return 1; }

 protected:
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    if (!d.has_scene || !(d.tau_c_s > 0)) return false;
    X.assign(1, {});
    const std::size_t P = d.shape.pixels();
    // tau = tau0 (1 + gamma (y_prev - y0)): d ln tau / d gamma = y_prev - y0.
    two_frame_derivative(d, d.tau_c_s, 1.0,
                         [&](int n, std::size_t p) { return double(d.baseline[std::size_t(n - 1) * P + p]) - d.level_mid; },
                         X[0]);
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override {
    return {{"gamma", beta[0]}, {"y0", data_->level_mid}};
  }
  // tau stays positive over the levels of the recording: |gamma| x (level range) well below 1.
  bool physical(int, const Eigen::VectorXd& beta) const override {
    const auto [lo, hi] = std::minmax_element(data_->baseline.begin(), data_->baseline.end());
    return std::fabs(beta[0]) * (*hi - *lo) < 0.5;
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return "tau_temperature:gamma=" + number(beta[0]);
  }
  std::string summary() const override { return "transients whose time constant grows with the pixel's level"; }
};

// Row k is read k * line_time later: it sees the input a little later, and the residual is that
// delay times the input's rate of change, carried on through the two-frame response. Three
// estimates of the rate, scored as alternatives: the baseline's central and forward frame
// differences (right for motion that is slow against the edges' widths; rows counted from the
// middle, as the rows' common delay is then the baseline's timing shift), and the input's change
// over one exposure along the scene's own motion, divided by the exposure (d/d(delay) of an
// exposure-long average; rows counted from row 0). A frame difference spreads a fast sharp edge's
// change over its whole frame-to-frame sweep; the exposure's share of the sweep sits where the
// delay acts.
class RollingReadout final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "rolling_readout"; }
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
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{"line_time_s", beta[0]}}; }
  // Rows are read after one another: a positive line time, all rows within one frame period.
  bool physical(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 && beta[0] * data_->shape.height < 1.0 / data_->fps;
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 ? "rolling_readout:line_time_s=" + number(beta[0]) : "";
  }
  std::string summary() const override { return "residual proportional to row index x temporal derivative (moving edges sheared)"; }

 private:
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
    std::vector<float> response;
    if (!delay_response(d, d.tau_c_s, response)) return false;
    const std::size_t P = d.shape.pixels();
    // Here the common delay is the effect's too: the baseline's timing shift, on frame differences,
    // cannot hold a delay of edges that cross pixels within an exposure.
    const int W = d.shape.width;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(d.gain * double((i % P) / W) * response[i]);
    return true;
  }
};

class Crosstalk final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "crosstalk"; }
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
        for (int c = 0; c < W; ++c) {
          // Edges clamp to the frame (the neighbour outside is the pixel itself).
          const float centre = b[r * W + c];
          const float up = r > 0 ? b[(r - 1) * W + c] : centre, down = r + 1 < H ? b[(r + 1) * W + c] : centre;
          const float left = c > 0 ? b[r * W + c - 1] : centre, right = c + 1 < W ? b[r * W + c + 1] : centre;
          x[r * W + c] = 0.25f * (up + down + left + right) - centre;
        }
    }
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{"epsilon", beta[0]}}; }
  bool physical(int, const Eigen::VectorXd& beta) const override { return beta[0] > 0 && beta[0] < 0.5; }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 ? "crosstalk:epsilon=" + number(beta[0]) : "";
  }
  std::string summary() const override { return "residual proportional to the Laplacian of the image (edges and hot spots)"; }
};

class Nonlinearity final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "nonlinearity"; }
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
    return {{"c", beta[0]}, {"y0", data_->level_mid}};
  }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return "nonlinearity:c=" + number(beta[0]);
  }
  std::string summary() const override { return "residual curved against the simulated level"; }
};

// y_n = alpha y_{n-1} + (1 - alpha) x_n: one step ahead, the residual moves towards the previous
// recorded frame by alpha.
class TemporalFilter final : public PooledLinear {
 public:
  bool refits_tau() const override { return true; }
  const char* id() const override { return "temporal_filter"; }
  int parameter_count() const override { return 1; }

 protected:
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    const std::vector<float>& r = *residual_;
    const std::size_t P = d.shape.pixels();
    X.assign(1, std::vector<float>(d.shape.size(), 0.0f));
    // A filter's pole is per frame: the residual's autocorrelation falls as alpha^k. Memory that
    // falls slower (a slowly changing scene, drift) is not this effect.
    {
      double r0 = 0, r1 = 0, r2 = 0;
      std::vector<float> mean(d.shape.n, 0.0f);
      for (int n = 0; n < d.shape.n; ++n) {
        const float* f = d.frame(r, n);
        const std::uint8_t* v = d.valid_frame(n);
        double s = 0, c = 0;
        for (std::size_t p = 0; p < P; ++p)
          if (v[p]) { s += f[p]; c += 1; }
        mean[n] = c > 0 ? float(s / c) : 0.0f;
      }
      for (int n = 2; n < d.shape.n; ++n) {
        const float *f = d.frame(r, n), *f1 = d.frame(r, n - 1), *f2 = d.frame(r, n - 2);
        const std::uint8_t *v = d.valid_frame(n), *v1 = d.valid_frame(n - 1), *v2 = d.valid_frame(n - 2);
        for (std::size_t p = 0; p < P; ++p) {
          if (!(v[p] && v1[p] && v2[p])) continue;
          const double a = f[p] - mean[n], b = f1[p] - mean[n - 1], c = f2[p] - mean[n - 2];
          r0 += a * a; r1 += a * b; r2 += a * c;
        }
      }
      const double rho1 = r0 > 0 ? r1 / r0 : 0, rho2 = r0 > 0 ? r2 / r0 : 0;
      if (rho1 > 0 && rho2 > rho1 * rho1 + 0.5 * (rho1 - rho1 * rho1) + 0.02) return false;
    }
    // The previous frame's residual without its frame mean: a filter acts on every pixel's own
    // noise, while a slow global drift would make any one-step predictor look good.
    for (int n = 1; n < d.shape.n; ++n) {
      const float *rp = d.frame(r, n - 1), *bp = d.frame(d.baseline, n - 1), *b = d.frame(d.baseline, n);
      const std::uint8_t* vp = d.valid_frame(n - 1);
      double sum = 0, count = 0;
      for (std::size_t p = 0; p < P; ++p)
        if (vp[p]) { sum += rp[p]; count += 1; }
      const float mean = count > 0 ? static_cast<float>(sum / count) : 0.0f;
      float* x = X[0].data() + std::size_t(n) * P;
      for (std::size_t p = 0; p < P; ++p) x[p] = vp[p] ? rp[p] - mean + bp[p] - b[p] : 0.0f;
    }
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{"alpha", beta[0]}}; }
  bool physical(int, const Eigen::VectorXd& beta) const override { return beta[0] > 0 && beta[0] < 1; }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 && beta[0] < 1 ? "temporal_filter:alpha=" + number(beta[0]) : "";
  }
  std::string summary() const override { return "each frame keeps a fixed share of the previous recorded frame (lag-1 memory per frame)"; }
};

}  // namespace

std::unique_ptr<Candidate> make_thermal_memory() { return std::make_unique<ThermalMemory>(); }
std::unique_ptr<Candidate> make_tau_temperature() { return std::make_unique<TauTemperature>(); }
std::unique_ptr<Candidate> make_rolling_readout() { return std::make_unique<RollingReadout>(); }
std::unique_ptr<Candidate> make_crosstalk() { return std::make_unique<Crosstalk>(); }
std::unique_ptr<Candidate> make_nonlinearity() { return std::make_unique<Nonlinearity>(); }
std::unique_ptr<Candidate> make_temporal_filter() { return std::make_unique<TemporalFilter>(); }

void tau_derivative(const DiagnoseData& d, double tau_c, std::vector<float>& out) {
  two_frame_derivative(d, tau_c, 1.0, [](int, std::size_t) { return 1.0; }, out);
}

}  // namespace bolo::diag
