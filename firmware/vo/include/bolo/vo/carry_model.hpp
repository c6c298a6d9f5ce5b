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

}  // namespace bolo::vo
