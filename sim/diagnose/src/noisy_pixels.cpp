#include "noisy_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bolo/effects/stats.hpp"

namespace bolo::diag {

namespace {

struct PixelSpread {
  double variance = 0;          // about the pixel's own mean
  double trimmed_variance = 0;  // the same without the pixel's two largest deviations
  int count = 0;
};

// Wilson-Hilferty: a sample variance of dof degrees of freedom against the true variance, as a
// standard normal score.
double variance_z(double sample_variance, double true_variance, double dof) {
  const double k = 2 / (9 * dof);
  return (std::cbrt(sample_variance / true_variance) - (1 - k)) / std::sqrt(k);
}

}  // namespace

bool noisy_pixels(const DiagnoseData& d, const std::vector<float>& r, Unexplained& u) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  if (N < 16) return false;
  // Only pixel-frames where the baseline holds still since the previous frame: blinking is a
  // property of the pixel's noise, and what a transient effect leaves at moving edges is not.
  auto still = [&](int n, std::size_t p) {
    if (n == 0 || !d.valid_frame(n)[p] || !d.valid_frame(n - 1)[p]) return false;
    const float b = d.frame(d.still_reference(), n)[p], b0 = d.frame(d.still_reference(), n - 1)[p];
    return holds_still(b, b0);
  };
  std::vector<PixelSpread> spread(P);
  std::vector<double> mean(P, 0.0), largest(P, 0.0), second(P, 0.0);
  for (int n = 0; n < N; ++n) {
    const float* rn = d.frame(r, n);
    for (std::size_t p = 0; p < P; ++p)
      if (still(n, p)) { mean[p] += rn[p]; ++spread[p].count; }
  }
  for (std::size_t p = 0; p < P; ++p) mean[p] /= std::max(1, spread[p].count);
  for (int n = 0; n < N; ++n) {
    const float* rn = d.frame(r, n);
    for (std::size_t p = 0; p < P; ++p) {
      if (!still(n, p)) continue;
      const double e = (rn[p] - mean[p]) * (rn[p] - mean[p]);
      spread[p].variance += e;
      if (e > largest[p]) { second[p] = largest[p]; largest[p] = e; }
      else if (e > second[p]) second[p] = e;
    }
  }
  std::vector<double> typical;
  typical.reserve(P);
  for (std::size_t p = 0; p < P; ++p) {
    PixelSpread& s = spread[p];
    if (s.count < 16) continue;
    s.trimmed_variance = (s.variance - largest[p] - second[p]) / (s.count - 3);
    s.variance /= (s.count - 1);
    typical.push_back(s.variance);
  }
  if (typical.size() < 64) return false;
  // The typical pixel's variance from the median of all: the few noisy ones do not move it. The
  // median of a chi-square over dof is (1 - 2/(9 dof))^3 of its mean.
  const double dof = double(N - 1);
  const double sigma2 = median_in_place(typical) / std::pow(1 - 2 / (9 * dof), 3);
  if (!(sigma2 > 0)) return false;
  // A pixel counts when its variance is far out (z > 6, about 1e-9 for white noise) even without
  // its two largest deviations, and by a visible amount: 1.75 times the typical variance (pixels'
  // noise differs by some 10-20 % on a real array, which a long recording would otherwise call
  // significant). So must its spread by the median absolute deviation: a pixel that blinks spends
  // much of its time away from its median, while a few large misses (an edge the baseline gets
  // slightly wrong, passing now and then) leave the bulk of its readings alone.
  // Nor on the paths moving edges take most often (fewer still frames than most pixels have):
  // there a small miss of the baseline repeats with every pass and looks like blinking.
  std::vector<int> counts;
  for (const PixelSpread& s : spread)
    if (s.count >= 16) counts.push_back(s.count);
  const int typical_count = median_of(counts);
  std::vector<std::uint8_t> noisy(P, 0);
  std::vector<float> readings, deviations;
  for (std::size_t p = 0; p < P; ++p) {
    const PixelSpread& s = spread[p];
    if (s.count < 16 || s.count < 0.8 * typical_count) continue;
    if (!(variance_z(s.variance, sigma2, s.count - 1) > 6 && variance_z(s.trimmed_variance, sigma2, s.count - 3) > 5 &&
          s.trimmed_variance > 1.75 * sigma2))
      continue;
    readings.clear();
    for (int n = 0; n < N; ++n)
      if (still(n, p)) readings.push_back(d.frame(r, n)[p]);
    const float median = median_of(readings);
    deviations.clear();
    for (float v : readings) deviations.push_back(std::fabs(v - median));
    const double robust_sigma = 1.4826 * median_in_place(deviations);
    noisy[p] = robust_sigma * robust_sigma > 1.75 * sigma2;
  }
  // Isolated: a cluster of noisy pixels is a region (a moving object the mask let through), not
  // a defect of single pixels.
  std::vector<std::size_t> isolated;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = std::size_t(y) * W + x;
      if (!noisy[p]) continue;
      bool alone = true;
      for (int dy = -1; dy <= 1 && alone; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int yy = y + dy, xx = x + dx;
          if ((dy || dx) && yy >= 0 && yy < H && xx >= 0 && xx < W && noisy[std::size_t(yy) * W + xx]) { alone = false; break; }
        }
      if (alone) isolated.push_back(p);
    }
  if (isolated.size() < 3) return false;
  double excess = 0;
  u.where.row0 = H;
  u.where.col0 = W;
  u.where.row1 = u.where.col1 = -1;
  for (std::size_t p : isolated) {
    excess += spread[p].variance - sigma2;
    const int y = int(p / std::size_t(W)), x = int(p % std::size_t(W));
    u.where.row0 = std::min(u.where.row0, y);
    u.where.row1 = std::max(u.where.row1, y);
    u.where.col0 = std::min(u.where.col0, x);
    u.where.col1 = std::max(u.where.col1, x);
  }
  u.where.frames = {{0, N - 1}};
  u.rms = std::sqrt(excess / double(isolated.size()));
  std::ostringstream t;
  t << isolated.size() << " isolated pixels whose residual fluctuates far more than the other pixels' (as blinking "
    << "or random-telegraph pixels do, or an event repeated at those pixels), e.g. at (row, col)";
  for (std::size_t i = 0; i < std::min<std::size_t>(5, isolated.size()); ++i)
    t << (i ? ", " : " ") << "(" << isolated[i] / std::size_t(W) << ", " << isolated[i] % std::size_t(W) << ")";
  u.where.summary = t.str();
  return true;
}

}  // namespace bolo::diag
