#pragma once
// Two-frame sensitivity: d(output)/d(parameter) propagated through the two-frame recursion, for
// the effects that act on the time constant (tau_temperature, tau_spread) and for the baseline's
// own tau as a nuisance regressor (pooled.cpp).

#include <cmath>
#include <vector>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// dc_n/dp and dk_n/dp come from `scale(n, p)` = d ln(tau)/dp at that pixel-frame.
template <typename Scale>
void two_frame_derivative(const DiagnoseData& d, double tau_c, Scale scale, std::vector<float>& out) {
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
}

// d(baseline)/d(ln tau).
inline void tau_derivative(const DiagnoseData& d, double tau_c, std::vector<float>& out) {
  two_frame_derivative(d, tau_c, [](int, std::size_t) { return 1.0; }, out);
}

}  // namespace bolo::diag
