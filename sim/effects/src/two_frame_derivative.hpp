#pragma once
// How the baseline moves when its time constants change: d(output)/d(parameter) along the baseline's
// own frame steps, for the effects that act on tau (tau_spread per pixel, tau_temperature by level)
// and for the baseline's own tau as a nuisance regressor (pooled.cpp).

#include <cmath>
#include <cstddef>
#include <vector>

#include "bolo/diagnose/data.hpp"
#include "bolo/effects/stats.hpp"

namespace bolo::diag {

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

// The baseline's recursion in input units, s_n = c_n s_{n-1} + w_n u_n (a restart from a level at
// the first frame and flagged shutter frames), with a derivative beside it,
// ds_n = c_n ds_{n-1} + source(n, p, s_{n-1}, u_n) (restart_source(n, p, level, u_n) on a restart);
// write(i, s_n, ds_n) for every pixel-frame i. False when the baseline has no steps (no scene).
template <typename Source, typename RestartSource, typename Write>
bool along_baseline_steps(const DiagnoseData& d, Source source, RestartSource restart_source, Write write) {
  const std::size_t P = d.shape.pixels();
  const int N = d.shape.n;
  const FrameSteps& f = d.steps;
  if (int(f.carry.size()) != N || int(d.steps_per_ln_tau.carry.size()) != N || d.input.size() != d.shape.size()) return false;
  std::vector<double> s(P), ds(P);
  for (int n = 0; n < N; ++n) {
    const float* u = d.frame(d.input, n);
    const bool restart = n == 0 || d.flagged_event[n];
    double level = 0;  // a shutter frame restarts from the scene's mean level, the first frame from its own input
    if (restart && n > 0) {
      for (std::size_t p = 0; p < P; ++p) level += u[p];
      level /= double(P);
    }
    for (std::size_t p = 0; p < P; ++p) {
      if (restart) {
        const double from = n == 0 ? u[p] : level;
        ds[p] = restart_source(n, p, from, double(u[p]));
        s[p] = f.restart[n] * from + f.weight[n] * u[p];
      } else {
        ds[p] = f.carry[n] * ds[p] + source(n, p, s[p], double(u[p]));
        s[p] = f.carry[n] * s[p] + f.weight[n] * u[p];
      }
      write(std::size_t(n) * P + p, s[p], ds[p]);
    }
  }
  return true;
}

// The slope of the baseline's term for motion within the exposure per ln tau_h at every pixel-frame
// is this factor times the term (lateness_per_ln_tau_h at the median exposure).
inline double within_exposure_per_ln_tau(const DiagnoseData& d) {
  if (d.within_exposure.size() != d.shape.size()) return 0.0;
  return lateness_per_ln_tau_h(median_of(d.exposure_s), d.tau_h_s > 0 ? d.tau_h_s : d.tau_c_s);
}

// d(output)/d(gamma) when both time constants follow the pixel's previous level,
// tau = tau0 (1 + gamma q_{n-1}) with q = level - `reference` (the baseline's), in a camera
// calibrated to read its input in steady state at every level (only the transient depends on gamma):
//   ds_n = c_n ds_{n-1} + q_{n-1} (c'_n s_{n-1} + (w'_n + w_n kappa') u_n),  out_n = gain (ds_n - kappa' q_n s_n),
// c', w' the steps' slopes per ln tau and kappa' = d ln(h / (1 - c)) / d(ln tau) at the median timing
// (the calibration's), plus q_{n-1} times the slope of the motion within the exposure.
inline void level_tau_derivative(const DiagnoseData& d, double reference, std::vector<float>& out) {
  out.assign(d.shape.size(), 0.0f);
  const double tau_c = d.tau_c_s, tau_h = d.tau_h_s > 0 ? d.tau_h_s : d.tau_c_s;
  const double x_h = median_of(d.exposure_s) / tau_h, x_c = median_of(d.readout_s) / tau_c;
  const double kappa_slope = -x_h / std::expm1(x_h) + x_c / std::expm1(x_c);
  const std::size_t P = d.shape.pixels();
  const FrameSteps &f = d.steps, &df = d.steps_per_ln_tau;
  auto previous_q = [&](int n, std::size_t p) { return d.baseline[std::size_t(n - 1) * P + p] - reference; };
  const bool ok = along_baseline_steps(
      d,
      [&](int n, std::size_t p, double s_prev, double u) {
        return previous_q(n, p) * (df.carry[n] * s_prev + (df.weight[n] + f.weight[n] * kappa_slope) * u);
      },
      [](int, std::size_t, double, double) { return 0.0; },
      [&](std::size_t i, double s, double ds) {
        out[i] = static_cast<float>(d.gain * (ds - kappa_slope * (d.baseline[i] - reference) * s));
      });
  if (!ok) return;
  const double k = within_exposure_per_ln_tau(d);
  if (k == 0) return;
  for (std::size_t i = P; i < out.size(); ++i) out[i] += static_cast<float>(k * (d.baseline[i - P] - reference) * d.within_exposure[i]);
}

// d(baseline)/d(ln tau), both time constants together: the baseline's own recursion differentiated
// frame by frame (the carry, the heating weight and the calibration at the median timing, which a
// jittered exposure or readout moves from frame to frame), plus its term for motion within the
// exposure, whose lateness a longer tau_h shortens.
inline void tau_derivative(const DiagnoseData& d, std::vector<float>& out) {
  out.assign(d.shape.size(), 0.0f);
  const FrameSteps& df = d.steps_per_ln_tau;
  const bool ok = along_baseline_steps(
      d, [&](int n, std::size_t, double s_prev, double u) { return df.carry[n] * s_prev + df.weight[n] * u; },
      [&](int n, std::size_t, double from, double u) { return df.restart[n] * from + df.weight[n] * u; },
      [&](std::size_t i, double, double ds) { out[i] = static_cast<float>(d.gain * ds); });
  if (!ok) return;
  const double k = within_exposure_per_ln_tau(d);
  for (std::size_t i = 0; k != 0 && i < out.size(); ++i) out[i] += static_cast<float>(k * d.within_exposure[i]);
}

}  // namespace bolo::diag
