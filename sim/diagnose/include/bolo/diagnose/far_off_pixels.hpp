#pragma once
// Pixels far off the model: stuck or dead ones, whose residual is not noise. A fit of something
// every pixel shares (the baseline's gain and tau, an in-core filter's pole) leaves them out; they
// stay in the data for dead_pixels.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bolo/diagnose/data.hpp"
#include "bolo/effects/stats.hpp"

namespace bolo::diag {

// 1 where the pixel's mean square of `residual(i)` over its valid pixel-frames exceeds 100 x the
// median pixel's (a clipped reading is off the model by design and is not valid).
template <typename Residual>
std::vector<std::uint8_t> far_off_pixels(const DiagnoseData& d, Residual residual) {
  const std::size_t P = d.shape.pixels();
  std::vector<double> ms(P, 0.0), count(P, 0.0);
  for (int n = 0; n < d.shape.n; ++n)
    for (std::size_t p = 0; p < P; ++p) {
      const std::size_t i = std::size_t(n) * P + p;
      if (!d.valid[i]) continue;
      const double e = residual(i);
      ms[p] += e * e;
      count[p] += 1;
    }
  for (std::size_t p = 0; p < P; ++p) ms[p] = count[p] > 0 ? ms[p] / count[p] : 0.0;
  std::vector<double> sorted = ms;
  const double typical = median_in_place(sorted);
  std::vector<std::uint8_t> far(P);
  for (std::size_t p = 0; p < P; ++p) far[p] = ms[p] > 100 * typical + 1e-12;
  return far;
}

}  // namespace bolo::diag
