// Per-pixel, per-column and per-row maps: offset_fpn, column_fpn, row_fpn, shading, gain_fpn,
// tau_spread, dead_pixels. A map is fitted on the training frames only and shrunk towards zero
// by its own noise (James-Stein), so a map made of noise predicts nothing on held-out blocks.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "dynamic_effects.hpp"
#include "stats.hpp"

namespace bolo::diag {
namespace {

Where whole(const DiagnoseData& d, std::string summary) {
  Where w;
  w.frames = {{0, d.shape.n - 1}};
  w.row1 = d.shape.height - 1;
  w.col1 = d.shape.width - 1;
  w.summary = std::move(summary);
  return w;
}

// Per pixel: sum and count of the residual, and (for slopes) sums against a regressor image.
struct PixelSums {
  std::vector<double> r, n, x, xr, xx;
  double residual_var = 0;  // residual variance about the pixel means (noise of the map)
};

PixelSums pixel_sums(const DiagnoseData& d, const std::vector<float>& r, const std::vector<char>& train,
                     const std::vector<float>* x) {
  const std::size_t P = d.shape.pixels();
  PixelSums s;
  s.r.assign(P, 0);
  s.n.assign(P, 0);
  if (x) { s.x.assign(P, 0); s.xr.assign(P, 0); s.xx.assign(P, 0); }
  double rr = 0;
  for (int f = 0; f < d.shape.n; ++f) {
    if (!train[f]) continue;
    const float* rf = d.frame(r, f);
    const std::uint8_t* v = d.valid_frame(f);
    const float* xf = x ? d.frame(*x, f) : nullptr;
    for (std::size_t p = 0; p < P; ++p) {
      if (!v[p]) continue;
      s.r[p] += rf[p];
      s.n[p] += 1;
      rr += double(rf[p]) * rf[p];
      if (xf) { s.x[p] += xf[p]; s.xr[p] += double(xf[p]) * rf[p]; s.xx[p] += double(xf[p]) * xf[p]; }
    }
  }
  double total = 0, means2 = 0;
  for (std::size_t p = 0; p < P; ++p) {
    total += s.n[p];
    if (s.n[p] > 0) means2 += s.r[p] * s.r[p] / s.n[p];
  }
  s.residual_var = total > P ? std::max(0.0, (rr - means2) / (total - double(P))) : rr / std::max(1.0, total);
  return s;
}

// Per pixel: the square of the mean level (sums taken against the baseline), NaN without data.
std::vector<double> squared_levels(const PixelSums& s) {
  std::vector<double> q(s.n.size(), NAN);
  for (std::size_t p = 0; p < s.n.size() && !s.x.empty(); ++p)
    if (s.n[p] > 0) q[p] = (s.x[p] / s.n[p]) * (s.x[p] / s.n[p]);
  return q;
}

// Shrinks `values` (estimates with noise variances `noise_var`) by one common factor.
double shrink(std::vector<double>& values, const std::vector<double>& noise_var) {
  double var = 0, nv = 0;
  std::size_t m = 0;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(noise_var[i])) { var += values[i] * values[i]; nv += noise_var[i]; ++m; }
  if (m == 0 || var <= 0) return 0.0;
  const double factor = std::max(0.0, 1.0 - nv / var);
  for (double& v : values) v *= factor;
  return factor;
}

// The static pattern r_p (centred time-averaged residual, noise variance v_p) as a zero-mean
// field whose variance is a part independent of the level (offset FPN: a) plus a part growing
// with the square of the pixel's level q_p = ybar_p^2 (gain FPN, y (1 + g): g ybar, b = var g).
// One static frame cannot tell g ybar from an offset pixel by pixel, but their spread over
// pixels of different level can: the three variance models are compared by likelihood.
struct LevelSplit {
  double offset_var = 0, gain_var = 0;  // a, b of the chosen model
  bool has_offset = true, has_gain = false;
  // Pixel p's share of the pattern that is gain: b q / (a + b q + v).
  double gain_share(double q, double v) const {
    const double total = offset_var + gain_var * q + v;
    return has_gain && total > 0 ? gain_var * q / total : 0.0;
  }
  double offset_share(double q, double v) const {
    const double total = offset_var + gain_var * q + v;
    return has_offset && total > 0 ? offset_var / total : 0.0;
  }
};

LevelSplit split_by_level(const std::vector<double>& r, const std::vector<double>& v, const std::vector<double>& q) {
  std::vector<std::size_t> use;
  double r2 = 0, qm = 0;
  for (std::size_t p = 0; p < r.size(); ++p)
    if (std::isfinite(v[p]) && std::isfinite(q[p]) && q[p] > 0) {
      use.push_back(p);
      r2 += r[p] * r[p];
      qm += q[p];
    }
  LevelSplit out;
  if (use.size() < 16 || !(r2 > 0) || !(qm > 0)) return out;
  r2 /= double(use.size());
  qm /= double(use.size());
  // The likelihood needs per pixel only (r^2, q, v): pixels sorted by level and pooled into at
  // most 1024 bins of neighbouring levels (exact up to 1024 pixels; the search below evaluates
  // it a few thousand times).
  std::sort(use.begin(), use.end(), [&](std::size_t x, std::size_t y) { return q[x] < q[y]; });
  struct Bin {
    double count = 0, r2 = 0, q = 0, v = 0;
  };
  std::vector<Bin> bins;
  const std::size_t per_bin = (use.size() + 1023) / 1024;
  for (std::size_t i = 0; i < use.size(); i += per_bin) {
    Bin b;
    for (std::size_t k = i; k < std::min(use.size(), i + per_bin); ++k) {
      const std::size_t p = use[k];
      b.count += 1, b.r2 += r[p] * r[p], b.q += q[p], b.v += v[p];
    }
    b.q /= b.count, b.v /= b.count;
    bins.push_back(b);
  }
  const auto ll = [&](double a, double b) {
    double sum = 0;
    for (const Bin& bin : bins) {
      const double var = a + b * bin.q + bin.v;
      if (!(var > 0)) return -std::numeric_limits<double>::infinity();
      sum -= 0.5 * (bin.count * std::log(var) + bin.r2 / var);
    }
    return sum;
  };
  // Golden-section search for the maximum of f on [0, hi].
  const auto argmax = [](const auto& f, double hi) {
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double lo = 0, x1 = hi - g * hi, x2 = g * hi, f1 = f(x1), f2 = f(x2);
    for (int i = 0; i < 40; ++i) {
      if (f1 < f2) { lo = x1; x1 = x2; f1 = f2; x2 = lo + g * (hi - lo); f2 = f(x2); }
      else { hi = x2; x2 = x1; f2 = f1; x1 = hi - g * (hi - lo); f1 = f(x1); }
    }
    return 0.5 * (lo + hi);
  };
  const double a_hi = 4 * r2, b_hi = 4 * r2 / qm;
  const double a_only = argmax([&](double a) { return ll(a, 0); }, a_hi);
  const double b_only = argmax([&](double b) { return ll(0, b); }, b_hi);
  // Both: a and b trade off along a ridge, so search the offset's fraction t of the pattern's
  // variance (a = t S, b q_mean = (1 - t) S) and, for each t, the scale S.
  const auto best_scale = [&](double t) { return argmax([&](double sc) { return ll(t * sc, (1 - t) * sc / qm); }, a_hi); };
  const double t = argmax([&](double x) {
    const double sc = best_scale(x);
    return ll(x * sc, (1 - x) * sc / qm);
  }, 1.0);
  const double scale = best_scale(t);
  const double a = t * scale, b = (1 - t) * scale / qm;
  const double ll_offset = ll(a_only, 0), ll_gain = ll(0, b_only), ll_both = std::max(ll(a, b), std::max(ll_offset, ll_gain));
  // Offset FPN is the default reading of a static pattern: the gain part must pay its BIC price
  // and a margin (a pattern on a scene of one level stays an offset pattern). Once it has, the
  // offset part stays unless it is plainly absent: a one-sided likelihood-ratio test at ~0.7 %
  // (a pure gain pattern fits a ~ 0 and gains nothing from it).
  const double price = 0.5 * std::log(double(use.size())) + 2.0;
  const bool gain_needed = ll_both - ll_offset > price;
  const bool offset_needed = ll_both - ll_gain > 3.0;
  if (gain_needed && offset_needed) {
    out.offset_var = a, out.gain_var = b, out.has_offset = true, out.has_gain = true;
  } else if (gain_needed) {
    out.gain_var = b_only, out.has_offset = false, out.has_gain = true;
  } else {
    out.offset_var = a_only;
  }
  return out;
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / double(v.size()));
}

// The time-averaged residual (training frames) and its column and row medians, centred, with
// whether they stand out as stripes.
struct TimeAveraged {
  int width = 0;
  std::vector<double> mean, noise, col, row;
  double typical_noise = 0;
  bool stripes_in_columns = false, stripes_in_rows = false;
  // The per-pixel pattern: the mean less the stripes (column and row medians that are no
  // stripes belong to the pixel pattern itself), centred.
  std::vector<double> pixel_pattern() const {
    std::vector<double> rest(mean.size());
    const std::size_t W = std::size_t(width);
    for (std::size_t p = 0; p < mean.size(); ++p)
      rest[p] = mean[p] - (stripes_in_columns ? col[p % W] : 0.0) - (stripes_in_rows ? row[p / W] : 0.0);
    const double m = std::accumulate(rest.begin(), rest.end(), 0.0) / double(rest.size());
    for (double& v : rest) v -= m;
    return rest;
  }
};

TimeAveraged time_averaged(const DiagnoseData& d, const PixelSums& s) {
  const int H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  TimeAveraged a;
  a.width = W;
  a.mean.assign(P, 0.0);
  a.noise.assign(P, INFINITY);
  for (std::size_t p = 0; p < P; ++p)
    if (s.n[p] > 0) { a.mean[p] = s.r[p] / s.n[p]; a.noise[p] = s.residual_var / s.n[p]; }
  // Columns and rows: medians, robust to the odd dead pixel.
  a.col.assign(W, 0.0);
  a.row.assign(H, 0.0);
  std::vector<double> tmp;
  a.typical_noise = s.residual_var / std::max(1.0, median_of(s.n));
  for (int c = 0; c < W; ++c) {
    tmp.clear();
    for (int rr = 0; rr < H; ++rr) tmp.push_back(a.mean[rr * W + c]);
    a.col[c] = median_in_place(tmp);
  }
  for (int rr = 0; rr < H; ++rr) {
    tmp.assign(a.mean.begin() + rr * W, a.mean.begin() + (rr + 1) * W);
    a.row[rr] = median_in_place(tmp);
  }
  auto centre = [](std::vector<double>& v) {
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
    for (double& x : v) x -= m;
  };
  centre(a.col);
  centre(a.row);
  // Stripes must stand out from what a pixel pattern's own column and row medians are: a
  // random per-pixel map of spread s has column medians of spread ~1.25 s / sqrt(rows).
  double pixel_spread = 0;
  for (std::size_t p = 0; p < P; ++p) {
    const double v = a.mean[p] - a.col[p % W] - a.row[p / W];
    pixel_spread += v * v;
  }
  pixel_spread = std::sqrt(pixel_spread / double(P));
  a.stripes_in_columns = rms(a.col) >= 2.0 * pixel_spread / std::sqrt(double(H));
  a.stripes_in_rows = rms(a.row) >= 2.0 * pixel_spread / std::sqrt(double(W));
  return a;
}

class StaticMapFit final : public FittedEffect {
 public:
  StaticMapFit(std::vector<float> map, nlohmann::json params, std::string sim, Where where)
      : map_(std::move(map)), params_(std::move(params)), sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int, std::span<float> out) const override { std::copy(map_.begin(), map_.end(), out.begin()); }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }

 private:
  std::vector<float> map_;
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

// The time-averaged residual split into columns, rows, a smooth radial field and the rest;
// each static-map effect takes its own part.
enum class StaticPart { offset, column, row, shading };

class StaticMap final : public Candidate {
 public:
  explicit StaticMap(StaticPart part) : part_(part) {}
  bool needs_distant_holdout() const override { return true; }
  const char* id() const override {
    switch (part_) {
      case StaticPart::offset: return "offset_fpn";
      case StaticPart::column: return "column_fpn";
      case StaticPart::row: return "row_fpn";
      case StaticPart::shading: return "shading";
    }
    return "";
  }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override { data_ = &d; residual_ = &r; }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const DiagnoseData& d = *data_;
    // A static background already holds every static pattern: nothing to fit.
    if (!d.has_scene) return nullptr;
    const int H = d.shape.height, W = d.shape.width;
    const std::size_t P = d.shape.pixels();
    const PixelSums s = pixel_sums(d, *residual_, train, part_ == StaticPart::offset ? &d.baseline : nullptr);
    TimeAveraged avg = time_averaged(d, s);
    std::vector<double>&mean = avg.mean, &noise = avg.noise, &col = avg.col, &row = avg.row;
    std::vector<double> noise_col(W, 1.57 * avg.typical_noise / H), noise_row(H, 1.57 * avg.typical_noise / W);
    // The radial field of the simulator's shading, (x_n^2 + y_n^2)/2 with x_n, y_n in [-1, 1].
    std::vector<double> field(P);
    double fm = 0;
    for (int rr = 0; rr < H; ++rr)
      for (int c = 0; c < W; ++c) {
        const double xn = 2.0 * c / std::max(1, W - 1) - 1, yn = 2.0 * rr / std::max(1, H - 1) - 1;
        field[rr * W + c] = 0.5 * (xn * xn + yn * yn);
        fm += field[rr * W + c];
      }
    fm /= double(P);
    double ff = 0, fr = 0;
    for (std::size_t p = 0; p < P; ++p) {
      const double f = field[p] - fm, rest = mean[p];
      ff += f * f;
      fr += f * rest;
    }
    const double amplitude = ff > 0 ? fr / ff : 0.0;
    const bool stripes_in_columns = avg.stripes_in_columns, stripes_in_rows = avg.stripes_in_rows;
    if (part_ == StaticPart::column && !stripes_in_columns) return nullptr;
    if (part_ == StaticPart::row && !stripes_in_rows) return nullptr;
    std::vector<float> map(P, 0.0f);
    nlohmann::json params;
    std::string sim;
    Where where;
    switch (part_) {
      case StaticPart::column: {
        shrink(col, noise_col);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(col[p % W]);
        params = {{"sigma", rms(col)}};
        sim = "column_fpn:sigma=" + number(rms(col));
        where = whole(d, "stripes: column means of the time-averaged residual");
        int worst = int(std::max_element(col.begin(), col.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }) - col.begin());
        where.summary += " (strongest column " + std::to_string(worst) + ")";
        break;
      }
      case StaticPart::row: {
        shrink(row, noise_row);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(row[p / W]);
        params = {{"sigma", rms(row)}};
        sim = "row_fpn:sigma=" + number(rms(row));
        where = whole(d, "stripes: row means of the time-averaged residual");
        break;
      }
      case StaticPart::shading: {
        // Noise of a one-parameter fit: residual variance over the pixel-frames times 1/sum f^2.
        const double a = amplitude;
        for (std::size_t p = 0; p < P; ++p) map[p] = float(a * (field[p] - fm));
        params = {{"amplitude", a}};
        sim = "shading:amplitude=" + number(a);
        where = whole(d, "smooth radial field of the time-averaged residual (centre to corners)");
        break;
      }
      case StaticPart::offset: {
        // What column and row stripes leave (they are effects of their own). The radial shading
        // field splits into a column and a row part, so shading competes with both and wins
        // with its single parameter when the pattern is radial.
        std::vector<double> rest = avg.pixel_pattern(), noise_rest = noise;
        // A pattern whose spread follows the level is gain_fpn's (its static part); where both
        // are there, this takes the offset's share of each pixel.
        const std::vector<double> level2 = squared_levels(s);
        const LevelSplit split = split_by_level(rest, noise_rest, level2);
        if (!split.has_offset) return nullptr;
        if (split.has_gain)
          for (std::size_t p = 0; p < P; ++p) rest[p] *= split.offset_share(level2[p], noise_rest[p]);
        else
          shrink(rest, noise_rest);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(rest[p]);
        // Beside a gain pattern the map holds each pixel's expected offset share (shrunk); the
        // spread is the variance component's.
        const double sigma = split.has_gain ? std::sqrt(split.offset_var) : rms(rest);
        params = {{"sigma", sigma}};
        sim = "offset_fpn:sigma=" + number(sigma);
        where = whole(d, "static pixel-to-pixel pattern in the time-averaged residual");
        break;
      }
    }
    return std::make_unique<StaticMapFit>(std::move(map), params, sim, where);
  }

 private:
  StaticPart part_;
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
};

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

class SlopeMap final : public Candidate {
 public:
  explicit SlopeMap(bool tau) : tau_(tau) {}
  bool needs_distant_holdout() const override { return true; }
  void release() override { x_.reset(); }
  const char* id() const override { return tau_ ? "tau_spread" : "gain_fpn"; }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    {
      auto x = std::make_shared<std::vector<float>>();
      if (tau_) {
        if (d.has_scene && d.tau_c_s > 0) tau_derivative(d, d.tau_c_s, *x);
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
    nlohmann::json params = {{"sigma", sigma}};
    std::string sim = (tau_ ? "tau_spread:sigma=" : "gain_fpn:sigma=") + number(sigma);
    Where where = whole(d, tau_ ? "per-pixel residual proportional to the input change (each pixel its own tau)"
                                : "per-pixel slope of the residual against the level");
    return std::make_unique<SlopeMapFit>(x_, std::move(map), std::move(icpt), std::move(centre), params, sim, where);
  }

 private:
  bool tau_;
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  std::shared_ptr<const std::vector<float>> x_;
};

// Stuck pixels: their reading does not follow the scene (no temporal variance while the
// sensor has noise) or sits far off every other pixel. The model reads them as constant.
class DeadFit final : public FittedEffect {
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
    return {{"count", pixels_.size()}, {"pixels_row_col", where}};
  }
  std::string simulator_effect() const override { return "dead_pixels:count=" + std::to_string(pixels_.size()); }
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

class DeadPixels final : public Candidate {
 public:
  const char* id() const override { return "dead_pixels"; }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override { data_ = &d; residual_ = &r; }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const DiagnoseData& d = *data_;
    const std::size_t P = d.shape.pixels();
    std::vector<double> sy(P, 0), syy(P, 0), sr(P, 0), cnt(P, 0);
    for (int n = 0; n < d.shape.n; ++n) {
      if (!train[n]) continue;
      const float *y = d.frame(d.recorded, n), *r = d.frame(*residual_, n);
      for (std::size_t p = 0; p < P; ++p) { sy[p] += y[p]; syy[p] += double(y[p]) * y[p]; sr[p] += r[p]; cnt[p] += 1; }
    }
    std::vector<double> sd(P), mr(P);
    for (std::size_t p = 0; p < P; ++p) {
      if (cnt[p] < 2) return nullptr;
      const double m = sy[p] / cnt[p];
      sd[p] = std::sqrt(std::max(0.0, syy[p] / cnt[p] - m * m));
      mr[p] = sr[p] / cnt[p];
    }
    std::vector<double> tmp = sd;
    const double typical_sd = median_in_place(tmp);
    tmp = mr;
    const double centre = median_in_place(tmp);
    for (double& v : tmp) v = std::fabs(v - centre);
    const double spread = 1.4826 * median_in_place(tmp) + 1e-9;
    std::vector<std::size_t> pixels;
    std::vector<float> value;
    for (std::size_t p = 0; p < P; ++p) {
      // Frozen while the sensor has noise, and reading far from what the model expects (a
      // pixel of a static, noise-free region would be frozen too, but not off the model).
      const bool frozen = typical_sd > 0.5 && sd[p] < 0.05 * typical_sd;
      const bool off = std::fabs(mr[p] - centre) > 10 * typical_sd + 25 * spread;
      if (frozen && off) { pixels.push_back(p); value.push_back(float(sy[p] / cnt[p])); }
    }
    if (pixels.empty() || pixels.size() > P / 20) return nullptr;
    return std::make_unique<DeadFit>(d, *residual_, std::move(pixels), std::move(value));
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
};

}  // namespace

std::unique_ptr<Candidate> make_offset_fpn() { return std::make_unique<StaticMap>(StaticPart::offset); }
std::unique_ptr<Candidate> make_column_fpn() { return std::make_unique<StaticMap>(StaticPart::column); }
std::unique_ptr<Candidate> make_row_fpn() { return std::make_unique<StaticMap>(StaticPart::row); }
std::unique_ptr<Candidate> make_shading() { return std::make_unique<StaticMap>(StaticPart::shading); }
std::unique_ptr<Candidate> make_gain_fpn() { return std::make_unique<SlopeMap>(false); }
std::unique_ptr<Candidate> make_tau_spread() { return std::make_unique<SlopeMap>(true); }
std::unique_ptr<Candidate> make_dead_pixels() { return std::make_unique<DeadPixels>(); }

std::vector<std::unique_ptr<Candidate>> make_catalogue() {
  std::vector<std::unique_ptr<Candidate>> c;
  c.push_back(make_ffc_step());
  c.push_back(make_fpa_drift());
  c.push_back(make_frame_duplication());
  c.push_back(make_dead_pixels());
  c.push_back(make_offset_fpn());
  c.push_back(make_column_fpn());
  c.push_back(make_row_fpn());
  c.push_back(make_shading());
  c.push_back(make_gain_fpn());
  c.push_back(make_tau_spread());
  c.push_back(make_thermal_memory());
  c.push_back(make_tau_temperature());
  c.push_back(make_rolling_readout());
  c.push_back(make_crosstalk());
  c.push_back(make_nonlinearity());
  c.push_back(make_temporal_filter());
  c.push_back(make_agc());
  return c;
}

}  // namespace bolo::diag
