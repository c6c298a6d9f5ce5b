// Online estimation of the bolometer time constants (ir, ir-loop). tau_h and tau_c are global
// parameters: every tracked frame whose carry-over chain is intact adds the information of the
// residual
//   r = raw_i(p') - alpha_i raw_{i-1}(p') - (beta_i / beta_h) (raw_h(p) - alpha_h raw_{h-1}(p))
// (Eq. 7 of Zhang et al. with the host keyframe's corrected intensity as the reference) over the
// patterns of the inlier points, at the tracked pose; the estimate takes a Gauss-Newton step with
// the information accumulated so far (recursive least squares, slow forgetting). With constant
// exposure tau_h only enters through beta_i / beta_h = 1, so a weak prior ties it to tau_c.

#include <cmath>

#include <Eigen/Cholesky>

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
    const double ratio = ci.beta / ch.beta;
    const double dratio_dh = (ci.dbeta_dtau_h * ch.beta - ci.beta * ch.dbeta_dtau_h) / (ch.beta * ch.beta);
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
        const double reference = p.raw[j] - ch.alpha * p.raw_prev[j];
        const double r = yi - ci.alpha * yp - ratio * reference;
        const double Jc = -ci.dalpha_dtau_c * yp + ratio * ch.dalpha_dtau_c * p.raw_prev[j];
        const double Jh = -dratio_dh * reference;
        const double w = huber_weight(static_cast<float>(r), hub);
        const Eigen::Vector2d J(Jh, Jc);
        H += w * J * J.transpose();
        g += w * J * r;
      }
    }
  }
  if (used < 20) return;
  // Slow forgetting: the estimate follows a drifting tau, older frames' linearisations fade.
  s.tau_info = 0.98 * s.tau_info + H;
  Eigen::Matrix2d A = s.tau_info;
  // Weak tie tau_h = tau_c (the data rarely sees tau_h) and a weak anchor at the current value.
  const double tie = 1e-3 * (A(1, 1) + 1.0);
  A(0, 0) += tie, A(1, 1) += tie, A(0, 1) -= tie, A(1, 0) -= tie;
  Eigen::Vector2d rhs = g;
  rhs(0) += tie * (s.tau.h - s.tau.c);
  rhs(1) -= tie * (s.tau.h - s.tau.c);
  A(0, 0) += 1e-6 * (A(0, 0) + 1.0), A(1, 1) += 1e-6 * (A(1, 1) + 1.0);
  const Eigen::Vector2d step = -A.ldlt().solve(rhs);
  // Bounded steps (20 % a frame) and a physical range keep a bad frame from throwing tau away.
  const auto bounded = [](double value, double delta) {
    const double limit = 0.2 * value;
    delta = std::max(-limit, std::min(limit, delta));
    return std::max(0.001, std::min(0.1, value + delta));
  };
  if (!std::isfinite(step(0)) || !std::isfinite(step(1))) return;
  s.tau.h = bounded(s.tau.h, step(0));
  s.tau.c = bounded(s.tau.c, step(1));
}

}  // namespace bolo::vo
