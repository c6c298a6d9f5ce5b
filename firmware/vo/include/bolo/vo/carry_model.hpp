#pragma once
// The microbolometer two-frame model in the VO's terms: raw_i = alpha_i * raw_{i-1} + beta_i * u,
// alpha_i = exp(-t_r,i-1 / tau_c) (what is left of the previous frame), beta_i = 1 - exp(-t_e,i /
// tau_h) (how far the pixel heats towards the scene u). With derivatives for tau estimation.

#include <cmath>

namespace bolo::vo {

struct Tau {
  double h = 0.010, c = 0.010;  // seconds
};

struct CarryCoefficients {
  double alpha = 0, beta = 1;
  double dalpha_dtau_c = 0, dbeta_dtau_h = 0;
};

// readout_prev_s: readout after the previous frame; exposure_s: this frame's exposure.
inline CarryCoefficients carry_coefficients(Tau tau, double readout_prev_s, double exposure_s) {
  CarryCoefficients k;
  k.alpha = std::exp(-readout_prev_s / tau.c);
  k.dalpha_dtau_c = k.alpha * readout_prev_s / (tau.c * tau.c);
  const double e = std::exp(-exposure_s / tau.h);
  k.beta = 1 - e;
  k.dbeta_dtau_h = -e * exposure_s / (tau.h * tau.h);
  return k;
}

// A frame right after a shutter event: the pixels had settled on the uniform shutter, so the
// frame reads beta_i u plus a constant, while a static scene point reads beta_ref u / (1 - alpha_ref)
// at the reference timing (the level the VO's tracking images are scaled to). The ratio, the
// frame's contrast against that level, depends on tau alone: with an even timing it is 1 - alpha.
inline double shutter_step_gain(Tau tau, double exposure_s, double reference_readout_s, double reference_exposure_s) {
  const CarryCoefficients now = carry_coefficients(tau, reference_readout_s, exposure_s);
  const CarryCoefficients ref = carry_coefficients(tau, reference_readout_s, reference_exposure_s);
  return now.beta * (1.0 - ref.alpha) / ref.beta;
}

// The tau (tau_h = tau_c) in [lo_s, hi_s] whose shutter_step_gain() is `gain`, by bisection on
// log tau (the gain falls as tau grows); 0 when no tau in the range gives it.
inline double tau_from_shutter_step_gain(double gain, double exposure_s, double reference_readout_s,
                                         double reference_exposure_s, double lo_s = 0.001, double hi_s = 0.1) {
  const auto at = [&](double t) { return shutter_step_gain({t, t}, exposure_s, reference_readout_s, reference_exposure_s); };
  if (!(gain < at(lo_s) && gain > at(hi_s))) return 0.0;
  double lo = std::log(lo_s), hi = std::log(hi_s);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (at(std::exp(mid)) > gain ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

}  // namespace bolo::vo
