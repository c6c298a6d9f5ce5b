// The map statistics of map_statistics.hpp.

#include "map_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "bolo/effects/stats.hpp"

namespace bolo::diag {

Where whole(const DiagnoseData& d, std::string summary) {
  Where w;
  w.frames = {{0, d.shape.n - 1}};
  w.row1 = d.shape.height - 1;
  w.col1 = d.shape.width - 1;
  w.summary = std::move(summary);
  return w;
}


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

std::vector<double> squared_levels(const PixelSums& s) {
  std::vector<double> q(s.n.size(), NAN);
  for (std::size_t p = 0; p < s.n.size() && !s.x.empty(); ++p)
    if (s.n[p] > 0) q[p] = (s.x[p] / s.n[p]) * (s.x[p] / s.n[p]);
  return q;
}

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


namespace {

// v less its least-squares quadratic in x in [-1, 1].
std::vector<double> without_quadratic(std::vector<double> v) {
  const std::size_t n = v.size();
  if (n < 4) return v;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  const auto basis = [n](std::size_t i) {
    const double x = 2.0 * double(i) / double(n - 1) - 1.0;
    return Eigen::Vector3d(1.0, x, x * x);
  };
  for (std::size_t i = 0; i < n; ++i) {
    normal += basis(i) * basis(i).transpose();
    rhs += basis(i) * v[i];
  }
  const Eigen::Vector3d c = normal.ldlt().solve(rhs);
  for (std::size_t i = 0; i < n; ++i) v[i] -= c.dot(basis(i));
  return v;
}

}  // namespace

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
  a.stripes_in_columns = rms(without_quadratic(a.col)) >= 2.0 * pixel_spread / std::sqrt(double(H));
  a.stripes_in_rows = rms(without_quadratic(a.row)) >= 2.0 * pixel_spread / std::sqrt(double(W));
  return a;
}

}  // namespace bolo::diag
