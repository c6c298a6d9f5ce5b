#pragma once
// Per-pixel, per-column and per-row maps of the time-averaged residual, the statistics the map
// effects (static_maps.cpp, slope_maps.cpp) fit on. A map is fitted on the training frames only
// and shrunk towards zero by its own noise (James-Stein), so a map made of noise predicts nothing
// on held-out blocks.

#include <numeric>
#include <string>
#include <vector>

#include "bolo/diagnose/candidate.hpp"
#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// The whole recording, every frame, row and column.
Where whole(const DiagnoseData& d, std::string summary);

// Per pixel: sum and count of the residual, and (for slopes) sums against a regressor image.
struct PixelSums {
  std::vector<double> r, n, x, xr, xx;
  double residual_var = 0;  // residual variance about the pixel means (noise of the map)
};

// Sums over the training frames' valid pixel-frames; against the regressor image x when given.
PixelSums pixel_sums(const DiagnoseData& d, const std::vector<float>& r, const std::vector<char>& train,
                     const std::vector<float>* x);

// Per pixel: the square of the mean level (sums taken against the baseline), NaN without data.
std::vector<double> squared_levels(const PixelSums& s);

// Shrinks `values` (estimates with noise variances `noise_var`) by one common factor.
double shrink(std::vector<double>& values, const std::vector<double>& noise_var);

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

LevelSplit split_by_level(const std::vector<double>& r, const std::vector<double>& v, const std::vector<double>& q);

double rms(const std::vector<double>& v);

// The time-averaged residual (training frames) and its column and row medians, centred, with
// whether they stand out as stripes. Stripes are column (row) FPN, independent from one column to
// the next: whether a profile holds them is judged on it less its smooth trend (a quadratic
// across the frame, which a shading left over or a scene's ghost also makes); a profile that
// does is taken whole.
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

TimeAveraged time_averaged(const DiagnoseData& d, const PixelSums& s);

}  // namespace bolo::diag
