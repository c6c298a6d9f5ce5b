// Online estimation of the bolometer time constants (ir, ir-loop). tau_h and tau_c are global
// parameters: every tracked frame whose carry-over chain is intact adds the information of the
// residual
//   r = u_i(p') - u_h(p),  u = (raw - alpha raw_prev) / beta
// (Eq. 7 of Zhang et al., divided by beta_i, with the host keyframe's corrected intensity as the
// reference) over the patterns of the inlier points, at the tracked pose; the estimate takes a
// Gauss-Newton step with
// the information accumulated so far (recursive least squares, slow forgetting). With constant
// exposure tau_h only scales u, which cancels between frames: tau_h and tau_c cannot be told
// apart, and one tau (tau_h = tau_c) is estimated.

#include <cmath>

#include "state.hpp"

namespace bolo::vo {

void store_raw_pattern(const State& s, Point& p) {
  const Image raw{s.raw.data(), s.cfg.width, s.cfg.height};
  const Image prev{s.raw_prev.data(), s.cfg.width, s.cfg.height};
  for (std::uint32_t j = 0; j < kPattern; ++j) {
    const float x = p.u + kPatternX[j], y = p.v + kPatternY[j];
    p.raw[j] = inside(raw, x, y, 1.0f) ? bilinear(raw, x, y) : 0.0f;
    p.raw_prev[j] = inside(prev, x, y, 1.0f) && s.have_prev ? bilinear(prev, x, y) : p.raw[j];
  }
}

void refine_tau(State& s) {
  if (!s.chain_ok) return;
  const Image raw{s.raw.data(), s.cfg.width, s.cfg.height};
  const Image prev{s.raw_prev.data(), s.cfg.width, s.cfg.height};
  const Scaled k = camera_at(s.cfg.camera, 0);
  const float hub = s.cfg.huber_counts;
  const CarryCoefficients ci = carry_coefficients(s.tau, s.readout_prev_s, s.exposure_s);
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  std::uint32_t used = 0;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    const Keyframe& host = s.kf[slot];
    if (!host.used || !host.chain_ok) continue;
    const CarryCoefficients ch = carry_coefficients(s.tau, host.readout_prev_s, host.exposure_s);
    const Se3 M = s.T_cw * host.T_cw.inverse();
    const Eigen::Matrix3f R = M.R.cast<float>();
    const Eigen::Vector3f t = M.t.cast<float>();
    for (std::uint32_t i = 0; i < host.count; ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active || !p.inlier) continue;
      const Eigen::Vector3f X = R * Eigen::Vector3f((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0f) + t * p.idepth;
      if (X.z() <= 1e-4f) continue;
      const float u = k.fx * X.x() / X.z() + k.cx, v = k.fy * X.y() / X.z() + k.cy;
      if (!inside(raw, u, v, 3.0f)) continue;
      ++used;
      for (std::uint32_t j = 0; j < kPattern; ++j) {
        const double yi = bilinear(raw, u + kPatternX[j], v + kPatternY[j]);
        const double yp = bilinear(prev, u + kPatternX[j], v + kPatternY[j]);
        // In scene units (u = (raw - alpha raw_prev) / beta): in raw units the residual shrinks
        // with beta, and the fit would drift to large tau just to shrink it.
        const double ui = (yi - ci.alpha * yp) / ci.beta;
        const double uh = (p.raw[j] - ch.alpha * p.raw_prev[j]) / ch.beta;
        const double r = ui - uh;
        const double Jc = -ci.dalpha_dtau_c * yp / ci.beta + ch.dalpha_dtau_c * p.raw_prev[j] / ch.beta;
        const double Jh = -ui * ci.dbeta_dtau_h / ci.beta + uh * ch.dbeta_dtau_h / ch.beta;
        const double w = huber_weight(static_cast<float>(r), hub);
        const Eigen::Vector2d J(Jh, Jc);
        H += w * J * J.transpose();
        g += w * J * r;
      }
    }
  }
  if (used < 20) return;
  // One tau for both: with tau_h = tau_c the information is J = J_h + J_c (see above).
  const double info = H(0, 0) + H(1, 1) + 2 * H(0, 1), grad = g(0) + g(1);
  // Slow forgetting: the estimate follows a drifting tau, older frames' linearisations fade.
  s.tau_info(0, 0) = 0.98 * s.tau_info(0, 0) + info;
  const double step = -grad / (s.tau_info(0, 0) + 1e-9);
  if (!std::isfinite(step)) return;
  // Bounded steps (10 % a frame) and a physical range keep a bad frame from throwing tau away.
  const double limit = 0.1 * s.tau.c;
  const double value = std::max(0.001, std::min(0.1, s.tau.c + std::max(-limit, std::min(limit, step))));
  s.tau.c = s.tau.h = value;
}

}  // namespace bolo::vo
