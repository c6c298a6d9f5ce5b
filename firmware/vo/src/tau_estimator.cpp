// Online estimation of the bolometer time constants (ir, ir-loop) from the carry-over between
// consecutive frames.
//
// A window point seen at p_i in frame i and at p_{i-1} in frame i-1 (tracked poses, its inverse
// depth) has one scene value u, so by the two-frame model y_i = alpha y_{i-1} + beta u (paper
// Eq. 7) at both pixels
//   A = y_i(p_i) - y_{i-1}(p_{i-1})   and   B = y_{i-1}(p_i) - y_{i-2}(p_{i-1})
// satisfy A = alpha B: beta and u cancel, and alpha = exp(-t_r / tau_c) is fitted by weighted
// least squares, alpha = sum(w A B) / sum(w B^2), from sums accumulated over frames. B is the
// carry-over that moved with the image: it is zero where the image does not change, so only
// moving edges inform tau (the estimate stays where it is while the camera is still).
//
// Why not against the host keyframe (u_i(p') - u_h(p), the first version): over the window's
// baselines the host's pattern is zoomed and sheared against the frame, and that error grows
// with 1/beta; the fit then drifted to a third of the true tau. Between consecutive frames the
// patterns match up to the sampling phase.
//
// tau_h is not observable here: with a constant exposure it only scales u, a gain the photometric
// model absorbs (the static level (1 - alpha) / beta * y does not depend on it when t_e = t_r).
// It is kept equal to tau_c.

#include <cmath>

#include "state.hpp"

namespace bolo::vo {
namespace {

constexpr double kForget = 0.995;      // per frame: a drifting tau is followed over ~200 frames
constexpr double kPriorWeight = 1e4;   // sum of B^2 the starting tau counts for (counts^2)
constexpr double kMinInformation = 1e6;  // sum of B^2 before the estimate moves (counts^2)

}  // namespace

void refine_tau(State& s) {
  if (!s.chain_ok || !s.chain_ok_prev || !s.prev_posed || s.kf_count == 0) return;
  const std::uint32_t w = s.cfg.width, h = s.cfg.height;
  const Image y0{s.raw.data(), w, h}, y1{s.raw_prev.data(), w, h}, y2{s.raw_prev2.data(), w, h};
  const Scaled k = camera_at(s.cfg.camera, 0);
  const float hub = s.cfg.huber_counts;
  const double readout = s.readout_prev_s;
  if (!(readout > 0)) return;
  const double alpha_now = std::exp(-readout / s.tau.c);
  double sab = 0, sbb = 0;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    const Keyframe& host = s.kf[slot];
    if (!host.used) continue;
    const Se3 Mi = s.T_cw * host.T_cw.inverse(), Mp = s.T_prev * host.T_cw.inverse();
    const Eigen::Matrix3f Ri = Mi.R.cast<float>(), Rp = Mp.R.cast<float>();
    const Eigen::Vector3f ti = Mi.t.cast<float>(), tp = Mp.t.cast<float>();
    for (std::uint32_t i = 0; i < host.count; ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active || !p.inlier) continue;
      const Eigen::Vector3f n((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0f);
      const Eigen::Vector3f Xi = Ri * n + ti * p.idepth, Xp = Rp * n + tp * p.idepth;
      if (Xi.z() <= 1e-4f || Xp.z() <= 1e-4f) continue;
      const float ui = k.fx * Xi.x() / Xi.z() + k.cx, vi = k.fy * Xi.y() / Xi.z() + k.cy;
      const float up = k.fx * Xp.x() / Xp.z() + k.cx, vp = k.fy * Xp.y() / Xp.z() + k.cy;
      if (!inside(y0, ui, vi, 3.0f) || !inside(y0, up, vp, 3.0f)) continue;
      for (std::uint32_t j = 0; j < kPattern; ++j) {
        const float oi_x = ui + kPatternX[j], oi_y = vi + kPatternY[j];
        const float op_x = up + kPatternX[j], op_y = vp + kPatternY[j];
        const double A = bilinear(y0, oi_x, oi_y) - bilinear(y1, op_x, op_y);
        const double B = bilinear(y1, oi_x, oi_y) - bilinear(y2, op_x, op_y);
        const double wt = huber_weight(static_cast<float>(A - alpha_now * B), hub);
        sab += wt * A * B;
        sbb += wt * B * B;
      }
    }
  }
  s.tau_sab = kForget * s.tau_sab + sab;
  s.tau_sbb = kForget * s.tau_sbb + sbb;
  s.tau_sbbr = kForget * s.tau_sbbr + sbb * readout;
  if (s.tau_sbb < kMinInformation) return;
  // The starting tau as a weak prior (pseudo-observations with B^2 summing to kPriorWeight).
  const double readout_mean = s.tau_sbbr / s.tau_sbb;
  const double alpha_init = std::exp(-readout_mean / static_cast<double>(s.cfg.tau_init_s));
  const double alpha = (s.tau_sab + kPriorWeight * alpha_init) / (s.tau_sbb + kPriorWeight);
  // A physical range: 1 ms .. 100 ms.
  const double lo = std::exp(-readout_mean / 0.001), hi = std::exp(-readout_mean / 0.1);
  const double a = std::max(lo, std::min(hi, alpha));
  const double tau = -readout_mean / std::log(a);
  if (!std::isfinite(tau)) return;
  s.tau.c = s.tau.h = tau;
}

}  // namespace bolo::vo
