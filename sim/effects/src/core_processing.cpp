// What the camera core does to its output: a recursive temporal filter, defective pixels, and
// repeated frames (agc, the core's tone mapping, has its own file).

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "bolo/effects/stats.hpp"
#include "bolo/diagnose/far_off_pixels.hpp"
#include "entries.hpp"
#include "map_statistics.hpp"
#include "params.hpp"
#include "pooled.hpp"

namespace bolo::effects {
namespace {

struct TemporalFilterSchema {
  static constexpr std::string_view id = "temporal_filter";
  static constexpr Param alpha{"alpha", "", 0.3, 0.0, 0.999};  // per frame
};

struct DeadPixelsSchema {
  static constexpr std::string_view id = "dead_pixels";
  // At most the pixel count.
  static constexpr Param count{"count", "pixels", 10, 0, std::numeric_limits<double>::infinity()};
};

struct FrameDuplicationSchema {
  static constexpr std::string_view id = "frame_duplication";
  static constexpr Param every{"every", "frames", 10, 2, 1e9};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// y[n] = alpha y[n-1] + (1 - alpha) x[n], per frame.
class TemporalFilterEffect final : public Effect {
  using S = effects::TemporalFilterSchema;

 public:
  TemporalFilterEffect(const EffectSpec& spec, const SimulationInfo&) {
    effects::Params p(spec);
    alpha_ = p.number(S::alpha);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void on_output(const FrameState&, std::span<double> y) override {
    if (previous_.size() != y.size()) {
      previous_.assign(y.begin(), y.end());
      return;
    }
    for (std::size_t p = 0; p < y.size(); ++p) {
      y[p] = alpha_ * previous_[p] + (1 - alpha_) * y[p];
      previous_[p] = y[p];
    }
  }
  nlohmann::json parameters() const override { return {{S::alpha.name, alpha_}}; }

 private:
  double alpha_;
  std::vector<double> previous_;
};

// `count` pixels stuck at 0 or at full scale (alternately), chosen by the seed.
class DeadPixelsEffect final : public Effect {
  using S = effects::DeadPixelsSchema;

 public:
  DeadPixelsEffect(const EffectSpec& spec, const SimulationInfo& info)
      : full_(static_cast<std::uint16_t>((1u << info.bits) - 1)),
        mask_(std::size_t{info.width} * info.height, 0) {
    effects::Params p(spec);
    const double max_count = static_cast<double>(mask_.size());
    count_ = static_cast<std::size_t>(p.number(S::count, S::count.fallback, max_count));
    p.finish();
    auto rng = effects::effect_rng(info.seed, id());
    std::vector<std::uint32_t> order(mask_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < count_; ++i) mask_[order[i]] = static_cast<std::uint8_t>(1 + i % 2);
  }
  const char* id() const override { return S::id.data(); }
  void on_counts(const FrameState&, std::span<std::uint16_t> counts) override {
    for (std::size_t p = 0; p < counts.size(); ++p)
      if (mask_[p]) counts[p] = mask_[p] == 1 ? 0 : full_;
  }
  nlohmann::json parameters() const override { return {{S::count.name, count_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{"dead_pixels_mask", std::vector<float>(mask_.begin(), mask_.end())}};
  }

 private:
  std::uint16_t full_;
  std::vector<std::uint8_t> mask_;
  std::size_t count_ = 0;
};

// Every `every`-th frame repeats the previous one bit for bit.
class FrameDuplicationEffect final : public Effect {
  using S = effects::FrameDuplicationSchema;

 public:
  FrameDuplicationEffect(const EffectSpec& spec, const SimulationInfo&) {
    effects::Params p(spec);
    every_ = static_cast<std::uint64_t>(p.number(S::every));
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void on_counts(const FrameState& f, std::span<std::uint16_t> counts) override {
    if (f.index % every_ == every_ - 1 && previous_.size() == counts.size()) {
      std::copy(previous_.begin(), previous_.end(), counts.begin());
      duplicated_.push_back(f.index);
    }
    previous_.assign(counts.begin(), counts.end());
  }
  nlohmann::json parameters() const override { return {{S::every.name, every_}, {"frames", duplicated_}}; }

 private:
  std::uint64_t every_;
  std::vector<std::uint16_t> previous_;
  std::vector<std::uint64_t> duplicated_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

// The residual's noise scale: 1.4826 x the median absolute deviation over a sample of the valid
// pixel-frames (a model's misses at moving edges are a minority and do not move it).
double residual_scale(const DiagnoseData& d, const std::vector<float>& r) {
  const std::size_t stride = std::max<std::size_t>(1, r.size() / 200000);
  std::vector<float> sample;
  for (std::size_t i = 0; i < r.size(); i += stride)
    if (d.valid[i]) sample.push_back(r[i]);
  if (sample.empty()) return 0.0;
  const float centre = median_of(sample);
  for (float& v : sample) v = std::fabs(v - centre);
  return 1.4826 * median_in_place(sample);
}

// Frame n reads what frame n-1 read, bit for bit (a few stuck pixels aside): a sensor with noise
// never does that.
bool repeats_previous(const DiagnoseData& d, int n) {
  const std::size_t P = d.shape.pixels();
  const float *y = d.frame(d.recorded, n), *yp = d.frame(d.recorded, n - 1);
  std::size_t same = 0;
  for (std::size_t p = 0; p < P; ++p) same += y[p] == yp[p];
  return same >= P - P / 1000;
}

// How far a one-frame memory of each pixel's own noise stands out of its sampling error: the
// lag-1 less the lag-2 correlation of the residual's fine structure (each pixel less the mean of
// its left and right neighbours) where the baseline changes by less than four noise scales from
// frame to frame, z against the spread over blocks of 10 frames. A filter keeps alpha of the noise
// for one frame and alpha^2 for two; what a scene model misses is smooth in the image (taken out
// by the neighbours) and in time (lags 1 and 2 alike), and line offsets cancel along the row.
// Frames next to a repeated one are left out: a repeat is a whole frame's memory (frame_duplication).
// NaN where the recording is too short to measure it (under 8 blocks): judged as other candidates.
double one_frame_memory_z(const DiagnoseData& d, const std::vector<float>& r, const std::vector<std::uint8_t>& far,
                          double noise_scale) {
  const int N = d.shape.n, W = d.shape.width, H = d.shape.height;
  const std::size_t P = d.shape.pixels();
  const std::vector<float>& still = d.still_reference();
  const float calm_step = 4.0f * static_cast<float>(noise_scale);
  std::vector<std::uint8_t> usable(P), usable1(P), usable2(P);
  auto mark = [&](int n, std::vector<std::uint8_t>& u) {
    const float *s = d.frame(still, n), *s1 = d.frame(still, n - 1);
    const std::uint8_t* v = d.valid_frame(n);
    for (std::size_t p = 0; p < P; ++p) u[p] = v[p] && !far[p] && std::fabs(s[p] - s1[p]) <= calm_step;
  };
  auto fine = [&](const float* f, std::size_t p) { return double(f[p]) - 0.5 * (double(f[p - 1]) + f[p + 1]); };
  constexpr int kBlock = 10;
  std::vector<char> repeat(N, 0);
  for (int n = 1; n < N; ++n) repeat[n] = repeats_previous(d, n);
  std::vector<double> b0, b1, b2;
  double count = 0;
  for (int n = 3; n < N; ++n) {
    if (n == 3) { mark(1, usable2); mark(2, usable1); }
    mark(n, usable);
    if ((n - 3) % kBlock == 0) { b0.push_back(0); b1.push_back(0); b2.push_back(0); }
    const float *f = d.frame(r, n), *f1 = d.frame(r, n - 1), *f2 = d.frame(r, n - 2);
    const bool beside_repeat = repeat[n] || repeat[n - 1];
    for (int y = 0; y < H && !beside_repeat; ++y)
      for (int x = 1; x + 1 < W; ++x) {
        const std::size_t p = std::size_t(y) * W + x;
        bool ok = true;
        for (std::size_t q = p - 1; q <= p + 1 && ok; ++q) ok = usable[q] && usable1[q] && usable2[q];
        if (!ok) continue;
        const double h = fine(f, p);
        b0.back() += h * h;
        b1.back() += h * fine(f1, p);
        b2.back() += h * fine(f2, p);
        count += 1;
      }
    std::swap(usable2, usable1);
    std::swap(usable1, usable);
  }
  const std::size_t B = b0.size();
  double s0 = 0, sd = 0;
  for (std::size_t b = 0; b < B; ++b) { s0 += b0[b]; sd += b1[b] - b2[b]; }
  if (B < 8 || count < 1000 || !(s0 > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double memory = sd / s0;
  double spread = 0;  // the ratio's sampling variance from the blocks' departures from it
  for (std::size_t b = 0; b < B; ++b) {
    const double e = (b1[b] - b2[b]) - memory * b0[b];
    spread += e * e;
  }
  const double se = std::sqrt(spread * double(B) / double(B - 1)) / s0;
  return se > 0 ? memory / se : 0.0;
}

// y_n = alpha y_{n-1} + (1 - alpha) x_n: one step ahead, the residual moves towards the previous
// recorded frame by alpha.
class TemporalFilterCandidate final : public PooledLinear {
  using S = effects::TemporalFilterSchema;

 public:
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    // A filter acts on every pixel alike: pixels far off the model (stuck ones) would set its pole.
    far_ = far_off_pixels(d, [&](std::size_t i) { return r[i]; });
    noise_scale_ = residual_scale(d, r);
    PooledLinear::prepare(d, r);
    signature_z_ = one_frame_memory_z(d, r, far_, noise_scale_);
  }
  void release() override {
    PooledLinear::release();
    far_ = {};
  }
  double signature_z() const override { return signature_z_; }
  bool refits_tau() const override { return true; }
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }
  int regressor_count() const override { return 2; }

 protected:
  bool regressors(int, Regressors& X) const override {
    const DiagnoseData& d = *data_;
    const std::vector<float>& r = *residual_;
    const std::size_t P = d.shape.pixels();
    const int N = d.shape.n;
    X.assign(2, std::vector<float>(d.shape.size(), 0.0f));
    // Judged where the baseline changes by less than half the residual's noise from one frame to
    // the next: what a model leaves where the input changes (motion within the exposure, a
    // moving edge) is correlated from frame to frame as the edge passes, and would read as a
    // filter. A recording without a still background (a pan) has such pixels in plenty; the
    // bitwise-still ones it lacks.
    const std::vector<float>& still = d.still_reference();
    const float quiet_step = 0.5f * static_cast<float>(noise_scale_);
    auto quiet = [&](int n, std::size_t p) {
      return std::fabs(d.frame(still, n)[p] - d.frame(still, n - 1)[p]) <= quiet_step;
    };
    const std::vector<std::uint8_t>& far = far_;
    auto quiet_pixel = [&](int n, std::size_t p) { return !far[p] && quiet(n, p); };
    std::vector<float> mean(N, 0.0f);
    for (int n = 0; n < N; ++n) {
      const float* f = d.frame(r, n);
      const std::uint8_t* v = d.valid_frame(n);
      double s = 0, c = 0;
      for (std::size_t p = 0; p < P; ++p)
        if (v[p] && !far[p]) { s += f[p]; c += 1; }
      mean[n] = c > 0 ? float(s / c) : 0.0f;
    }
    // A filter's pole is per frame: the residual's autocorrelation falls as alpha^k. Memory that
    // falls slower (a slowly changing scene, drift, a static pattern) is not this effect; it is
    // refused when its lag-2 correlation stands above a filter's by more than its sampling error.
    {
      double r0 = 0, r1 = 0, r2 = 0, count = 0;
      for (int n = 2; n < N; ++n) {
        const float *f = d.frame(r, n), *f1 = d.frame(r, n - 1), *f2 = d.frame(r, n - 2);
        const std::uint8_t *v = d.valid_frame(n), *v1 = d.valid_frame(n - 1), *v2 = d.valid_frame(n - 2);
        for (std::size_t p = 0; p < P; ++p) {
          if (!(v[p] && v1[p] && v2[p]) || !quiet_pixel(n, p) || !quiet(n - 1, p)) continue;
          const double a = f[p] - mean[n], b = f1[p] - mean[n - 1], c = f2[p] - mean[n - 2];
          r0 += a * a; r1 += a * b; r2 += a * c; count += 1;
        }
      }
      if (count < 1000) return false;
      const double rho1 = r1 / r0, rho2 = r2 / r0;
      if (rho1 > 0 && rho2 > rho1 * rho1 + 0.5 * (rho1 - rho1 * rho1) + 0.02 + 3 / std::sqrt(count)) return false;
    }
    // The previous frame's residual without its frame mean: a filter acts on every pixel's own
    // noise, while a slow global drift would make any one-step predictor look good. The filter's
    // share of the baseline's own change (alpha times its step) is left out: below half the noise
    // it is lost in it, and what a model misses where the input changes (a rolling readout, motion
    // within the exposure) is proportional to that step too.
    // The part of that change the frame's own timing makes is kept, as a second regressor: a
    // jittered exposure or readout moves every pixel's level from frame to frame, and the filter
    // drags each frame back towards the previous level by alpha, in every pixel alike, a global
    // fluctuation that would otherwise cut the effective samples. It is the baseline less its run
    // at the median timing (zero when the timing never changes), with a coefficient of its own,
    // since the baseline's tau_c takes up part of that lag.
    const bool timing_varies = !d.baseline_nominal.empty();
    for (int n = 1; n < N; ++n) {
      const float* rp = d.frame(r, n - 1);
      const std::uint8_t* vp = d.valid_frame(n - 1);
      const float *b = d.frame(d.baseline, n), *bp = d.frame(d.baseline, n - 1);
      const float *s = d.frame(still, n), *sp = d.frame(still, n - 1);
      float* x = X[0].data() + std::size_t(n) * P;
      float* xt = X[1].data() + std::size_t(n) * P;
      for (std::size_t p = 0; p < P; ++p) {
        if (!(vp[p] && quiet_pixel(n, p))) continue;
        x[p] = rp[p] - mean[n - 1];
        if (timing_varies) xt[p] = (bp[p] - b[p]) - (sp[p] - s[p]);
      }
    }
    return true;
  }
  nlohmann::json params_of(int, const Eigen::VectorXd& beta) const override { return {{S::alpha.name, beta[0]}}; }
  bool physical(int, const Eigen::VectorXd& beta) const override { return beta[0] > 0 && beta[0] < 1; }
  std::string simulator_text(int, const Eigen::VectorXd& beta) const override {
    return beta[0] > 0 && beta[0] < 1 ? effects::SpecText(S::id).set(S::alpha, number(beta[0])).str() : "";
  }
  std::string summary() const override { return "each frame keeps a fixed share of the previous recorded frame (lag-1 memory per frame)"; }

 private:
  std::vector<std::uint8_t> far_;  // pixels far off the model, for this round's residual
  double noise_scale_ = 0.0;
  double signature_z_ = 0.0;
};

// Stuck pixels: their reading does not follow the scene (no temporal variance while the
// sensor has noise) or sits far off every other pixel. The model reads them as constant.
class DeadFit final : public FittedEffect {
  using S = effects::DeadPixelsSchema;

 public:
  DeadFit(const DiagnoseData& d, const std::vector<float>& r, std::vector<std::size_t> pixels, std::vector<float> value)
      : d_(d), r_(r), pixels_(std::move(pixels)), value_(std::move(value)) {}
  void predict(int n, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), 0.0f);
    const float *y = d_.frame(d_.recorded, n), *r = d_.frame(r_, n);
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      const std::size_t p = pixels_[i];
      out[p] = r[p] - (y[p] - value_[i]);
    }
  }
  nlohmann::json params() const override {
    nlohmann::json where = nlohmann::json::array();
    for (std::size_t i = 0; i < std::min<std::size_t>(pixels_.size(), 50); ++i)
      where.push_back({pixels_[i] / d_.shape.width, pixels_[i] % d_.shape.width});
    return {{S::count.name, pixels_.size()}, {"pixels_row_col", where}};
  }
  std::string simulator_effect() const override {
    return effects::SpecText(S::id).set(S::count, std::to_string(pixels_.size())).str();
  }
  Where where() const override {
    Where w = whole(d_, std::to_string(pixels_.size()) + " isolated pixel(s) that do not follow the scene");
    return w;
  }

 private:
  const DiagnoseData& d_;
  const std::vector<float>& r_;
  std::vector<std::size_t> pixels_;
  std::vector<float> value_;
};

class DeadPixelsCandidate final : public Candidate {
  using S = effects::DeadPixelsSchema;

 public:
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override { data_ = &d; residual_ = &r; }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const DiagnoseData& d = *data_;
    const std::size_t P = d.shape.pixels();
    std::vector<double> sy(P, 0), syy(P, 0), sr(P, 0), srr(P, 0), cnt(P, 0);
    for (int n = 0; n < d.shape.n; ++n) {
      if (!train[n]) continue;
      const float *y = d.frame(d.recorded, n), *r = d.frame(*residual_, n);
      for (std::size_t p = 0; p < P; ++p) {
        sy[p] += y[p]; syy[p] += double(y[p]) * y[p]; sr[p] += r[p]; srr[p] += double(r[p]) * r[p]; cnt[p] += 1;
      }
    }
    std::vector<double> sd(P), mr(P), sdr(P);
    for (std::size_t p = 0; p < P; ++p) {
      if (cnt[p] < 2) return nullptr;
      const double m = sy[p] / cnt[p];
      sd[p] = std::sqrt(std::max(0.0, syy[p] / cnt[p] - m * m));
      mr[p] = sr[p] / cnt[p];
      sdr[p] = std::sqrt(std::max(0.0, srr[p] / cnt[p] - mr[p] * mr[p]));
    }
    std::vector<double> tmp = sd;
    const double typical_sd = median_in_place(tmp);
    tmp = sdr;
    const double typical_sdr = median_in_place(tmp);
    tmp = mr;
    const double centre = median_in_place(tmp);
    for (double& v : tmp) v = std::fabs(v - centre);
    const double spread = 1.4826 * median_in_place(tmp) + 1e-9;
    std::vector<std::size_t> pixels;
    std::vector<float> value;
    for (std::size_t p = 0; p < P; ++p) {
      // Frozen while the sensor has noise, and reading far from what the model expects (a
      // pixel of a static, noise-free region would be frozen too, but not off the model): on
      // average, or, in a moving scene, frame by frame (a pixel frozen at some reading of a
      // panning scene is off the model in every frame while its mean residual stays small, and
      // 10 x typical_sd, the readings' spread, which a pan makes hundreds of counts, hid it).
      const bool frozen = typical_sd > 0.5 && sd[p] < 0.05 * typical_sd;
      const bool off = std::fabs(mr[p] - centre) > 10 * typical_sd + 25 * spread || sdr[p] > 10 * typical_sdr + 1e-9;
      if (frozen && off) { pixels.push_back(p); value.push_back(float(sy[p] / cnt[p])); }
    }
    if (pixels.empty() || pixels.size() > P / 20) return nullptr;
    return std::make_unique<DeadFit>(d, *residual_, std::move(pixels), std::move(value));
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
};

// Frames that repeat their predecessor bit for bit. The fit learns the period and phase from
// the training frames; held out, the repeats it predicts must be there.
class DuplicateFit final : public FittedEffect {
  using S = effects::FrameDuplicationSchema;

 public:
  DuplicateFit(const DiagnoseData& d, const std::vector<float>& r, int period, int phase, std::vector<int> repeats)
      : d_(d), r_(r), period_(period), phase_(phase), repeats_(std::move(repeats)) {}
  // The period where the training blocks show one; and every frame the bit-identity test flags,
  // held-out ones included: that test is a fixed rule read off each frame (as a stuck pixel's
  // value is), not a parameter fitted to them, and noise never passes it.
  bool acts_on(int n) const override {
    return n > 0 && ((period_ > 0 && n % period_ == phase_) || std::binary_search(repeats_.begin(), repeats_.end(), n));
  }
  void predict(int n, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), 0.0f);
    if (!acts_on(n)) return;
    // The repeat reads what the previous frame read: residual becomes y_n - y_{n-1}.
    const float *y = d_.frame(d_.recorded, n), *yp = d_.frame(d_.recorded, n - 1), *r = d_.frame(r_, n);
    for (std::size_t p = 0; p < out.size(); ++p) out[p] = r[p] - (y[p] - yp[p]);
  }
  nlohmann::json params() const override {
    return {{S::every.name, period_}, {"frames", repeats_}};
  }
  std::string simulator_effect() const override {
    return period_ > 0 ? effects::SpecText(S::id).set(S::every, std::to_string(period_)).str() : "";
  }
  Where where() const override {
    Where w;
    for (int n : repeats_) w.frames.push_back({n - 1, n});
    w.row1 = d_.shape.height - 1;
    w.col1 = d_.shape.width - 1;
    w.summary = std::to_string(repeats_.size()) + " frame(s) identical to their predecessor" +
                (period_ > 0 ? ", every " + std::to_string(period_) + " frames" : "");
    return w;
  }

 private:
  const DiagnoseData& d_;
  const std::vector<float>& r_;
  int period_, phase_;
  std::vector<int> repeats_;
};

class FrameDuplicationCandidate final : public Candidate {
  using S = effects::FrameDuplicationSchema;

 public:
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }
  bool scored_where_it_acts() const override { return true; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    repeats_.clear();
    for (int n = 1; n < d.shape.n; ++n)
      if (repeats_previous(d, n)) repeats_.push_back(n);
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    std::vector<int> seen;
    for (int n : repeats_)
      if (train[n]) seen.push_back(n);
    if (repeats_.empty()) return nullptr;
    // The most common gap between repeats, if it explains all of them, is the period.
    int period = 0, phase = 0;
    if (seen.size() >= 2) {
      std::map<int, int> gaps;
      for (std::size_t i = 1; i < seen.size(); ++i) ++gaps[seen[i] - seen[i - 1]];
      int g = 0;
      for (auto [gap, count] : gaps) {
        bool divides = true;
        for (auto [other, c] : gaps) divides = divides && other % gap == 0;
        if (divides) { g = gap; break; }
      }
      if (g > 1) { period = g; phase = seen[0] % g; }
    }
    return std::make_unique<DuplicateFit>(*data_, *residual_, period, phase, repeats_);
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  std::vector<int> repeats_;
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry temporal_filter() {
  using S = TemporalFilterSchema;
  return make_entry<sim::TemporalFilterEffect, diag::TemporalFilterCandidate>(S::id, {S::alpha});
}

EffectEntry dead_pixels() {
  using S = DeadPixelsSchema;
  return make_entry<sim::DeadPixelsEffect, diag::DeadPixelsCandidate>(S::id, {S::count});
}

EffectEntry frame_duplication() {
  using S = FrameDuplicationSchema;
  return make_entry<sim::FrameDuplicationEffect, diag::FrameDuplicationCandidate>(S::id, {S::every});
}

}  // namespace bolo::effects
