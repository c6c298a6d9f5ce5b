#pragma once
// How the baseline moves when its time constants change, for the effects that act on tau and for
// the baseline's own tau as a nuisance regressor (pooled.cpp). Two readings of d/d(ln tau):
//  * on the transients as observed (transient_tau_derivative, level_tau_derivative): the input
//    recovered from the baseline frame by frame, so a jittered timing's level steps count as input
//    changes; a uniform tau and a level-dependent one's part at the reference level are then the
//    same shape, which the candidates that refit tau rely on;
//  * along the baseline's own frame steps (frame_step_tau_derivative): each frame's carry, heating
//    weight and calibration at the median timing, which a jittered exposure or readout moves per
//    frame, so a pixel's own tau moves its level with every frame's timing (tau_spread's map).

#include <cmath>
#include <cstddef>
#include <vector>

#include "bolo/diagnose/data.hpp"
#include "bolo/diagnose/frame_start.hpp"
#include "bolo/effects/stats.hpp"

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

// How much later than its even average an exposure weighed by the pixel's response,
// exp(-(t_e - t)/tau_h), reads the input: t_e (1/(1 - e^-x) - 1/x - 1/2), x = t_e/tau_h (seconds).
inline double exposure_lateness_s(double exposure_s, double tau_h) {
  const double x = exposure_s / tau_h;
  return exposure_s * (x < 1e-6 ? x / 12 : 1 / -std::expm1(-x) - 1 / x - 0.5);
}

// d ln(lateness)/d ln tau_h.
inline double lateness_per_ln_tau_h(double exposure_s, double tau_h) {
  constexpr double h = 1e-4;
  const double up = exposure_lateness_s(exposure_s, tau_h * std::exp(h)), down = exposure_lateness_s(exposure_s, tau_h * std::exp(-h));
  return up > 0 && down > 0 ? (std::log(up) - std::log(down)) / (2 * h) : 0.0;
}

// d(baseline)/d(ln tau), both time constants together, along the baseline's frame steps
// (d.steps, d.steps_per_ln_tau; input units, times the gain; restarting where the baseline does,
// frame_start), plus the slope of its term for motion within the exposure (the lateness per
// ln tau_h times d.within_exposure). Left empty without steps.
inline void frame_step_tau_derivative(const DiagnoseData& d, std::vector<float>& out) {
  const std::size_t P = d.shape.pixels();
  const int N = d.shape.n;
  const FrameSteps &f = d.steps, &df = d.steps_per_ln_tau;
  out.clear();
  if (int(f.carry.size()) != N || int(df.carry.size()) != N || d.input.size() != d.shape.size()) return;
  out.assign(d.shape.size(), 0.0f);
  std::vector<double> s(P), ds(P);
  for (int n = 0; n < N; ++n) {
    const float* u = d.frame(d.input, n);
    float* o = out.data() + std::size_t(n) * P;
    const FrameStart start = frame_start(d, d.input, n);
    for (std::size_t p = 0; p < P; ++p) {
      if (start.kind != FrameStart::carried) {
        const double from = start.kind == FrameStart::own_input ? double(u[p]) : start.level;
        ds[p] = df.restart[n] * from + df.weight[n] * u[p];
        s[p] = f.restart[n] * from + f.weight[n] * u[p];
      } else {
        ds[p] = df.carry[n] * s[p] + f.carry[n] * ds[p] + df.weight[n] * u[p];
        s[p] = f.carry[n] * s[p] + f.weight[n] * u[p];
      }
      o[p] = static_cast<float>(d.gain * ds[p]);
    }
  }
  if (d.within_exposure.size() != out.size()) return;
  const double k = lateness_per_ln_tau_h(median_of(d.exposure_s), d.tau_h_s > 0 ? d.tau_h_s : d.tau_c_s);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] += static_cast<float>(k * d.within_exposure[i]);
}

}  // namespace bolo::diag
