#pragma once
// How the baseline moves when its time constants change, for the effects that act on tau and for
// the baseline's own tau as a nuisance regressor (pooled.cpp). Two readings of d/d(ln tau):
//  * on the transients as observed (here: transient_tau_derivative, level_tau_derivative): the
//    input recovered from the baseline frame by frame, so a jittered timing's level steps count as
//    input changes; a uniform tau and a level-dependent one's part at the reference level are then
//    the same shape, which the candidates that refit tau rely on;
//  * along the baseline's own frame steps (DiagnoseData::baseline_per_ln_tau, from the baseline
//    fit): each frame's carry, heating weight and calibration at the median timing, which a
//    jittered exposure or readout moves per frame, so a pixel's own tau moves its level with every
//    frame's timing (tau_spread's map).

#include <cmath>
#include <cstddef>
#include <vector>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// d(baseline)/d(ln tau_c) through the two-frame recursion, s_n = c s_{n-1} + (1 - c) u_n, with u_n
// recovered from the baseline (units of the recording).
inline void transient_tau_derivative(const DiagnoseData& d, double tau_c, std::vector<float>& out) {
  const std::size_t P = d.shape.pixels();
  out.assign(d.shape.size(), 0.0f);
  std::vector<double> ds(P, 0.0);
  for (int n = 1; n < d.shape.n; ++n) {
    const double c = std::exp(-d.readout_s[n - 1] / tau_c);
    const double dc_dlntau = c * d.readout_s[n - 1] / tau_c;
    const float* b = d.frame(d.baseline, n);
    const float* bp = d.frame(d.baseline, n - 1);
    float* o = out.data() + std::size_t(n) * P;
    for (std::size_t p = 0; p < P; ++p) {
      const double u = (b[p] - c * bp[p]) / (1 - c);
      ds[p] = dc_dlntau * (bp[p] - u) + c * ds[p];
      o[p] = static_cast<float>(ds[p]);
    }
  }
}

// d(output)/d(gamma) when both time constants follow the pixel's previous level,
// tau = tau0 (1 + gamma q_{n-1}) with q = level - `reference`, in a camera calibrated to read its
// input in steady state at every level (only the transient depends on gamma):
//   E_n = c_n E_{n-1} + (q_{n-1} - q_n) (c'_n / (1 - c_n) q_{n-1} + kappa'_n q_n),
// c' = dc/d(ln tau_c), kappa' = d ln(h / (1 - c)) / d(ln tau) (h the exposure's heating share).
// Another reference adds a multiple of d(baseline)/d(ln tau).
inline void level_tau_derivative(const DiagnoseData& d, double tau_c, double tau_h, double reference,
                                 std::vector<float>& out) {
  const std::size_t P = d.shape.pixels();
  out.assign(d.shape.size(), 0.0f);
  std::vector<double> e(P, 0.0);
  for (int n = 1; n < d.shape.n; ++n) {
    const double c = std::exp(-d.readout_s[n - 1] / tau_c), x_h = d.exposure_s[n] / tau_h;
    const double h = -std::expm1(-x_h);
    const double dc_share = c * d.readout_s[n - 1] / tau_c / (1 - c);
    const double kappa_slope_n = -x_h * std::exp(-x_h) / h + dc_share;
    const float* b = d.frame(d.baseline, n);
    const float* bp = d.frame(d.baseline, n - 1);
    float* o = out.data() + std::size_t(n) * P;
    for (std::size_t p = 0; p < P; ++p) {
      const double q = b[p] - reference, qp = bp[p] - reference;
      e[p] = c * e[p] + (qp - q) * (dc_share * qp + kappa_slope_n * q);
      o[p] = static_cast<float>(e[p]);
    }
  }
}

}  // namespace bolo::diag
