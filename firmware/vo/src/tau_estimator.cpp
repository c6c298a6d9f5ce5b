// Online estimation of the bolometer time constants (ir, ir-loop) from the carry-over between
// consecutive frames.
//
// A window point seen at p_i in frame i and at p_{i-1} in frame i-1 (tracked poses, its inverse
// depth) has one scene value u, so by the two-frame model y_i = alpha y_{i-1} + beta u (paper
// Eq. 7) at both pixels
//   A = y_i(p_i) - y_{i-1}(p_{i-1})   and   B = y_{i-1}(p_i) - y_{i-2}(p_{i-1})
// satisfy A = alpha B: beta and u cancel, and alpha = exp(-t_r / tau_c) is fitted by weighted
// least squares, alpha = sum(w A B) / sum(w B^2), from sums accumulated over frames. B is the
// carry-over that moved with the image: zero where the image does not change, so only moving
// edges inform tau. Consecutive frames, not the host keyframe, because over a keyframe baseline
// the pattern is zoomed and sheared against the frame.
//
// Contract of the fit, and why each part is there:
// * Each frame's pairs are fitted jointly in alpha, the poses of frames i and i-1 and every
//   point's inverse depth, and only the information alpha keeps once those are eliminated (Schur
//   complement) is summed: the frame was tracked on the image made with the current tau, and
//   pairs sampled at that pose would otherwise lean towards the current alpha.
// * The pixel noise's expected share (from the measured noise, noise_estimator.cpp, and each
//   sample's interpolation weights, less the inverse depth's leverage) comes off alpha's entries
//   before the elimination: noise in B biases alpha low, and the elimination leaves it a larger
//   share.
// * A and B are sampled with Keys' cubic: interpolation errors that depend on the sub-pixel
//   position are nearly the same in consecutive frames and would pull alpha towards 1.
// * Active points count up to 4x the tracker's outlier cut: the tracker's inliers are judged on
//   the current-tau image and would favour the current alpha; the cut keeps the garbage of the
//   first frames after initialisation out.
// * The d r / d p Jacobians are central differences of the raw frames' combinations the samples
//   come from, not the (low-passed) tracking images' gradients, so they match the samples.
// * Across a change of exposure or readout each pair also has a constant of its own frame, which
//   takes up a camera's offset; see refine_tau.
//
// Shutter events (FrameInput::shutter_event) measure tau at first order where the camera reports
// them: the next frame's contrast against the static level is a known function of tau
// (shutter_step_gain, carry_model.hpp), read from the gain that frame is tracked with. Once one
// was measured, tau follows those measurements.
//
// tau_h is not observable here: with a constant exposure it only scales u, and the tracking
// images are scaled back to the static raw level (scene_level_scale), so it cancels. It is kept
// equal to tau_c. How well all this does on simulated sequences: docs/odometry-study.md, "τ".

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "tau_estimator.hpp"

#include "frame_state.hpp"
#include "map.hpp"
#include "motion_model.hpp"
#include "photometric_math.hpp"

namespace bolo::vo {
namespace {

constexpr double kForget = 0.995;      // per frame: a drifting tau is followed over ~200 frames
constexpr double kPriorWeight = 1e4;   // sum of B^2 the starting tau counts for (counts^2)
constexpr double kMinInformation = 1e6;  // sum of B^2 before the estimate moves (counts^2)
// ... and the share of it that is not pixel noise: below, the pairs hold too little carry-over
// to correct for the noise reliably, and the estimate stays where it is. The noise is measured
// on the flattest blocks of the frame difference, where moving fine texture passes for noise, so
// a noise-dominated fit would over-correct (scripts/study/plane-render.sh shows such frames).
constexpr double kMinSignalShare = 0.5;
// Points whose last tracked pattern energy exceeds this many of the tracker's outlier cuts are
// left out (wrong depth, occlusion); the tracker's own cut would favour pairs that agree with
// the current tau (the inliers are judged on the image made with it).
constexpr float kOutlierCutoffs = 4.0f;
// A pixel whose raw value did not change at this many checks (every other frame, so over 8
// frames), while it differs from its neighbours, is stuck (dead, or a hot pixel clipped at the
// sensor's range): a live pixel under noise keeps its exact value that often with vanishing
// probability, and never stands that far from all its neighbours. Every other frame, because the
// check reads two whole frames.
constexpr std::uint8_t kStuckChecks = 4;
constexpr float kStuckContrast = 64.0f;  // counts from each of its four neighbours
// A shutter event's step response is taken within this factor of the current tau.
constexpr double kShutterTauRange = 2.0;

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;
using Vec14 = Eigen::Matrix<double, 14, 1>;
using Mat14 = Eigen::Matrix<double, 14, 14>;
using Mat26 = Eigen::Matrix<double, 2, 6>;

// The fit's parameters: the poses of frames i and i-1 (6 each), across a change of timing a
// constant of the frame (kConstant), and alpha (kAlpha).
constexpr int kConstant = 12, kAlpha = 13;

// Alpha's information haa and gradient ga, less what the first N parameters (the nuisance: the
// poses, and the constant where it is fitted) take with them when they are eliminated. A tiny
// damping keeps a pose no point constrains solvable.
template <int N>
void eliminate_nuisance(const Mat14& H, const Vec14& g, double& haa, double& ga) {
  Eigen::Matrix<double, N, N> Hpp = H.topLeftCorner<N, N>();
  for (int q = 0; q < N; ++q) Hpp(q, q) = Hpp(q, q) * (1 + 1e-6) + 1e-9;
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(Hpp);
  const Eigen::Matrix<double, N, 1> x = ldlt.solve(H.block<N, 1>(0, kAlpha));
  haa -= H.block<N, 1>(0, kAlpha).dot(x);
  ga -= x.dot(g.head<N>());
}

// Per pattern sample: its weight, B's noise variance, the covariance of r's and B's noise, and
// d r / d inverse depth (the slope the depth's elimination follows).
struct PatternNoise {
  double weight, var_b, cov_rb, slope;
};
// Along one axis: a sample's sum of squared weights (its noise variance per unit pixel variance),
// and the sum over pixels of two samples' weight products (their noise covariance).
double sum_of_squares(const CubicTaps& t) {
  double sum = 0;
  for (const float v : t.w) sum += double{v} * v;
  return sum;
}
double overlap(const CubicTaps& a, const CubicTaps& b) {
  double sum = 0;
  for (int i = 0; i < 4; ++i) {
    const std::int32_t k = a.first + i - b.first;
    if (k >= 0 && k < 4) sum += double{a.w[i]} * b.w[k];
  }
  return sum;
}

// The central-difference gradient of ca img_a + cb img_b, bilinear at (x, y): the 4 x 4 block
// starting at the cubic taps' first pixels holds the four neighbours of (x, y) and their
// neighbours.
Eigen::Vector2d combined_gradient(const Image& img_a, double ca, const Image& img_b, double cb, const CubicTaps& tx,
                                  const CubicTaps& ty, float x, float y) {
  double d[4][4];
  for (std::size_t j = 0; j < 4; ++j) {
    const std::size_t row = (static_cast<std::size_t>(ty.first) + j) * img_a.width + static_cast<std::size_t>(tx.first);
    for (std::size_t k = 0; k < 4; ++k) d[j][k] = ca * img_a.data[row + k] + cb * img_b.data[row + k];
  }
  const double fx = x - static_cast<float>(tx.first + 1), fy = y - static_cast<float>(ty.first + 1);
  Eigen::Vector2d corner[2][2];
  for (std::size_t b = 0; b < 2; ++b)
    for (std::size_t a = 0; a < 2; ++a)
      corner[b][a] = {0.5 * (d[b + 1][a + 2] - d[b + 1][a]), 0.5 * (d[b + 2][a + 1] - d[b][a + 1])};
  const Eigen::Vector2d top = corner[0][0] + fx * (corner[0][1] - corner[0][0]);
  const Eigen::Vector2d bottom = corner[1][0] + fx * (corner[1][1] - corner[1][0]);
  return top + fy * (bottom - top);
}

// d pixel / d (translation, rotation) of a left perturbation of the camera pose (the tracker's
// convention); X is the point in the camera times its inverse depth.
Mat26 pixel_jacobian(const Scaled& k, const Eigen::Vector3f& X, float idepth) {
  const double x = X.x() / X.z(), y = X.y() / X.z(), iz = idepth / X.z();
  Mat26 D;
  D << k.fx * iz, 0, -k.fx * x * iz, -k.fx * x * y, k.fx * (1 + x * x), -k.fx * y,  //
      0, k.fy * iz, -k.fy * y * iz, -k.fy * (1 + y * y), k.fy * x * y, k.fy * x;
  return D;
}

// Whether a stuck pixel (count_unchanged_frames) lies within `reach` pixels of (u, v). A stuck
// pixel in a sample's interpolation footprint puts its step against the live neighbours
// (thousands of counts for a dead one) into A and B alike, which reads as alpha = 1.
bool stuck_pixel_near(const TauEstimator& est, const VoConfig& cfg, float u, float v, int reach) {
  const int w = static_cast<int>(cfg.width), h = static_cast<int>(cfg.height);
  const int cu = static_cast<int>(u), cv = static_cast<int>(v);
  for (int y = std::max(cv - reach, 0); y <= std::min(cv + reach + 1, h - 1); ++y)
    for (int x = std::max(cu - reach, 0); x <= std::min(cu + reach + 1, w - 1); ++x)
      if (est.unchanged_frames[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] >= kStuckChecks)
        return true;
  return false;
}

}  // namespace

void count_unchanged_frames(TauEstimator& est, const CurrentFrame& f, const MapCore& map) {
  est.stuck_check_due = !est.stuck_check_due;
  if (!est.stuck_check_due) return;
  // A frame counts only while a neighbour changes and the pixel differs from each of its four
  // neighbours: a region where nothing changes (a uniform surface in a noise-free render, its
  // edge included) is not stuck, and a live pixel of a low-noise camera may keep its value for a
  // few frames where it looks like its surroundings.
  const std::size_t w = map.cfg.width, h = map.cfg.height;
  const float contrast = kStuckContrast * map.intensity;
  std::uint32_t stuck = 0;
  // Indices from the frame's start: the row above is i - w, never a pointer stepped before a row.
  const float* y = f.raw.data();
  const float* p = f.raw_prev.data();
  std::uint8_t* count = est.unchanged_frames.data();
  for (std::size_t row = 1; row + 1 < h; ++row) {
    for (std::size_t i = row * w + 1; i + 1 < (row + 1) * w; ++i) {
      const float v = y[i];
      if (v != p[i]) {  // nearly every pixel under noise
        if (count[i] != 0) count[i] = 0;
        continue;
      }
      const bool neighbour_changed =
          y[i - 1] != p[i - 1] || y[i + 1] != p[i + 1] || y[i - w] != p[i - w] || y[i + w] != p[i + w];
      const bool apart = std::fabs(v - y[i - 1]) > contrast && std::fabs(v - y[i + 1]) > contrast &&
                         std::fabs(v - y[i - w]) > contrast && std::fabs(v - y[i + w]) > contrast;
      if (neighbour_changed && apart && count[i] < 255) ++count[i];
      stuck += count[i] >= kStuckChecks;
    }
  }
  est.stuck_pixels = stuck;
}

bool take_shutter_measurement(TauEstimator& t, double tau_s) {
  // A camera may deliver the first frame only once the pixels have settled on the scene again
  // (the gain then reads ~1 and tau ~1 ms), or repeat a frame across the event: a measurement
  // far from the current estimate is not taken (the carry-over pairs read within ~50 % of it).
  if (!(tau_s > 0 && tau_s < kShutterTauRange * t.tau.c && tau_s * kShutterTauRange > t.tau.c)) return false;
  // The latest event weighs as much as all before it: tau drifts with the focal plane's
  // temperature, and the events are seconds to minutes apart.
  if (t.shutter_measurements == 0) {
    t.shutter_tau = tau_s;
  } else {
    const double change = tau_s - t.shutter_tau;
    t.shutter_tau += 0.5 * change;
    t.shutter_tau_var = 0.5 * (t.shutter_tau_var + 0.5 * change * change);
  }
  ++t.shutter_measurements;
  t.tau.c = t.tau.h = t.shutter_tau;
  return true;
}

void refine_tau(TauEstimator& est, const MapCore& map, const CurrentFrame& f, const MotionModel& motion, double pixel_noise_var) {
  // A shutter event's step response measures alpha from the whole frame's contrast (first order);
  // the pairs see it only through how the image motion changes (second order), which the
  // images' smoothness biases (docs/odometry-study.md, "τ"). So the events, once there, decide.
  if (est.shutter_measurements > 0) return;
  if (!f.chain_ok || !f.chain_ok_prev || !motion.prev_posed || map.kf_count == 0) return;
  const std::uint32_t w = map.cfg.width, h = map.cfg.height;
  const Image y0{f.raw.data(), w, h}, y1{f.raw_prev.data(), w, h}, y2{f.raw_prev2.data(), w, h};
  const Scaled k = camera_at(map.cfg.camera, 0);
  const float hub = huber_threshold(map);
  const float outlier_energy = kOutlierCutoffs * tracking_cutoff(hub, 0);
  const double readout = f.readout_prev_s;
  if (!(readout > 0)) return;
  // Frames whose timing changes: y_i - alpha_i y_{i-1} = beta_i u and y_{i-1} - alpha_{i-1} y_{i-2} =
  // beta_{i-1} u, so with rho = beta_i / beta_{i-1} and kappa = alpha_{i-1} / alpha_i (both at the
  // current tau) A = y_i(p_i) - rho y_{i-1}(p_{i-1}) and B = y_{i-1}(p_i) - rho kappa y_{i-2}(p_{i-1})
  // satisfy A = alpha_i B. Both are exactly 1 for a constant timing. Where the exposure changes, B
  // holds (1 - rho) times the static level: the step response, a first-order measure of alpha.
  const double readout_before = f.readout_prev2_s > 0 ? f.readout_prev2_s : readout;
  const bool timing_changed = f.exposure_s != f.exposure_prev_s || readout_before != readout;
  const CarryCoefficients now_k = carry_coefficients(est.tau, readout, f.exposure_s);
  const CarryCoefficients prev_k = carry_coefficients(est.tau, readout_before, f.exposure_prev_s);
  const double alpha_now = now_k.alpha;
  const double rho = now_k.beta / prev_k.beta, rho_kappa = rho * (prev_k.alpha / now_k.alpha);
  // Then rho and kappa move with tau too: d r / d alpha_i = -y_{i-1}(p_i) + c_prev y_{i-2}(p_{i-1})
  // - c_rho (y_{i-1}(p_{i-1}) - alpha_{i-1} y_{i-2}(p_{i-1})), which is -B for a constant timing
  // (the fit is then Gauss-Newton, one step a frame; the noise correction below stays B's).
  // test_vo_board's exposure-switching wall checks the estimate across such changes.
  // A camera's raw counts start from an offset o, not from 0: y_i - o = beta_i u + alpha_i (y_{i-1}
  // - o). For a constant timing o cancels in A and B; across a change A - alpha_i B = o ((1 -
  // alpha_i) - rho (1 - alpha_{i-1})), the same at every pixel, which the step response would read
  // as alpha. Such a frame's fit has a
  // constant of its own, eliminated with the poses: the step's contrast across the scene still
  // measures alpha, its mean level no longer does.
  const double c_prev = rho * prev_k.dalpha_dtau_c / now_k.dalpha_dtau_c;
  const double drho_dtau = (now_k.dbeta_dtau_h * prev_k.beta - now_k.beta * prev_k.dbeta_dtau_h) / (prev_k.beta * prev_k.beta);
  const double c_rho = drho_dtau / now_k.dalpha_dtau_c;
  // Normal equations of r = A - alpha B (- c across a change of timing) in x = (pose of frame i,
  // pose of frame i-1, c, alpha), the points' inverse depths already eliminated; linearised at the
  // tracked poses, c = 0 and alpha_now. c's row and column stay empty for a constant timing.
  // A pattern pixel's Jacobian is T v with v = (d r / d p_i, d r / d p_{i-1}, d r / d alpha), where
  // d r / d p_i = grad(y_i - alpha y_{i-1}) at p_i, d r / d p_{i-1} = -grad(rho y_{i-1} - alpha rho
  // kappa y_{i-2}) at p_{i-1} (combined_gradient), and T holds the centre pixel's
  // projection Jacobians (as in the tracker): each point sums the 5x5 S = sum w v v^T and maps it
  // once.
  const double noise_var = pixel_noise_var;
  Mat14 H = Mat14::Zero();
  Vec14 g = Vec14::Zero();
  double noise_bb = 0;  // the noise's share of alpha's information, as eliminated below
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    const Keyframe& host = map.kf[slot];
    if (!host.used) continue;
    const Se3 Mi = motion.T_cw * host.T_cw.inverse(), Mp = motion.T_prev * host.T_cw.inverse();
    const Eigen::Matrix3f Ri = Mi.R.cast<float>(), Rp = Mp.R.cast<float>();
    const Eigen::Vector3f ti = Mi.t.cast<float>(), tp = Mp.t.cast<float>();
    for (std::uint32_t i = 0; i < host.count; ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active || p.energy > outlier_energy) continue;
      const Eigen::Vector3f n((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0f);
      const Eigen::Vector3f Xi = Ri * n + ti * p.idepth, Xp = Rp * n + tp * p.idepth;
      if (Xi.z() <= 1e-4f || Xp.z() <= 1e-4f) continue;
      const float ui = k.fx * Xi.x() / Xi.z() + k.cx, vi = k.fy * Xi.y() / Xi.z() + k.cy;
      const float up = k.fx * Xp.x() / Xp.z() + k.cx, vp = k.fy * Xp.y() / Xp.z() + k.cy;
      // The pattern reaches 2 pixels out, its gradients and the cubic taps 2 more.
      if (!inside(y0, ui, vi, 4.0f) || !inside(y0, up, vp, 4.0f)) continue;
      if (est.stuck_pixels > 0 && (stuck_pixel_near(est, map.cfg, ui, vi, 4) || stuck_pixel_near(est, map.cfg, up, vp, 4))) continue;
      // d p_i / d inverse depth and d p_{i-1} / d inverse depth.
      const Eigen::Vector2d c_px(k.fx * (ti.x() * Xi.z() - Xi.x() * ti.z()) / (Xi.z() * Xi.z()),
                                 k.fy * (ti.y() * Xi.z() - Xi.y() * ti.z()) / (Xi.z() * Xi.z()));
      const Eigen::Vector2d c_pp(k.fx * (tp.x() * Xp.z() - Xp.x() * tp.z()) / (Xp.z() * Xp.z()),
                                 k.fy * (tp.y() * Xp.z() - Xp.y() * tp.z()) / (Xp.z() * Xp.z()));
      Vec5 sr = Vec5::Zero();
      Mat5 S = Mat5::Zero();
      // c's entries (d r / d c = -1): its column of S, its diagonal, and its part of sr.
      Vec5 s_c = Vec5::Zero();
      double s_cc = 0, sr_c = 0;
      PatternNoise noise[kPattern];
      for (std::uint32_t j = 0; j < kPattern; ++j) {
        const float oi_x = ui + kPatternX[j], oi_y = vi + kPatternY[j];
        const float op_x = up + kPatternX[j], op_y = vp + kPatternY[j];
        const CubicTaps ix = cubic_taps(oi_x), iy = cubic_taps(oi_y), px = cubic_taps(op_x), py = cubic_taps(op_y);
        const double y1i = cubic(y1, ix, iy), y1p = cubic(y1, px, py), y2p = cubic(y2, px, py);
        const double A = cubic(y0, ix, iy) - rho * y1p;
        const double B = y1i - rho_kappa * y2p;
        const double jac_alpha = timing_changed ? -y1i + c_prev * y2p - c_rho * (y1p - prev_k.alpha * y2p) : -B;
        const double r0 = A - alpha_now * B;
        const double wt = huber_weight(static_cast<float>(r0), hub);
        // B's noise variance, and its covariance with r0's: A's y_{i-1} at p_{i-1} and B's at p_i
        // share pixels when the two positions are within two pixels.
        const double var_b =
            noise_var * (sum_of_squares(ix) * sum_of_squares(iy) + rho_kappa * rho_kappa * sum_of_squares(px) * sum_of_squares(py));
        const double cov_ab = -rho * noise_var * overlap(ix, px) * overlap(iy, py);
        noise[j] = {wt, var_b, cov_ab - alpha_now * var_b, 0.0};
        const Eigen::Vector2d now = combined_gradient(y0, 1.0, y1, -alpha_now, ix, iy, oi_x, oi_y);
        const Eigen::Vector2d before = combined_gradient(y1, -rho, y2, alpha_now * rho_kappa, px, py, op_x, op_y);
        Vec5 v;
        v << now.x(), now.y(), before.x(), before.y(), jac_alpha;
        add_weighted_outer_upper(S, v, wt);
        sr += (wt * r0) * v;
        if (timing_changed) s_c -= wt * v, s_cc += wt, sr_c -= wt * r0;
        noise[j].slope = v.head<4>().dot(Eigen::Vector4d(c_px.x(), c_px.y(), c_pp.x(), c_pp.y()));
      }
      S.triangularView<Eigen::StrictlyLower>() = S.triangularView<Eigen::StrictlyUpper>().transpose();
      const Mat26 Di = pixel_jacobian(k, Xi, p.idepth), Dp = pixel_jacobian(k, Xp, p.idepth);
      Vec5 c;
      c << c_px.x(), c_px.y(), c_pp.x(), c_pp.y(), 0.0;
      // The noise's expected share of S's and sr's alpha entries, less the part the inverse
      // depth's elimination removes with it (its leverage), taken out before that elimination.
      double e_bb = 0, e_br = 0, lev = 0, lev_bb = 0, lev_br = 0;
      for (const PatternNoise& q : noise) {
        const double wq2 = q.weight * q.slope * q.slope;
        e_bb += q.weight * q.var_b, e_br += q.weight * q.cov_rb;
        lev += wq2, lev_bb += q.weight * wq2 * q.var_b, lev_br += q.weight * wq2 * q.cov_rb;
      }
      if (lev > 0) e_bb -= lev_bb / lev, e_br -= lev_br / lev;
      S(4, 4) -= e_bb;
      sr(4) += e_br;
      noise_bb += e_bb;
      // The point's inverse depth eliminated: S - S c c^T S / (c^T S c), sr likewise.
      const Vec5 Sc = S * c;
      const double hdd = c.dot(Sc);
      if (hdd > 0) {
        const double inv = 1.0 / (hdd * (1 + 1e-6));
        if (timing_changed) {
          const double cs = s_c.dot(c);
          s_c -= (inv * cs) * Sc, s_cc -= inv * cs * cs, sr_c -= inv * c.dot(sr) * cs;
        }
        S.noalias() -= (inv * Sc) * Sc.transpose();
        sr -= (inv * c.dot(sr)) * Sc;
      }
      // H += T S T^T and g += T sr, with T = diag(Di^T, Dp^T, 1) taken block by block: the dense
      // 13x5 product went through Eigen's general matrix product, a quarter of this function's
      // instructions.
      const Eigen::Matrix<double, 6, 5> DiS = Di.transpose() * S.topRows<2>();
      const Eigen::Matrix<double, 6, 5> DpS = Dp.transpose() * S.middleRows<2>(2);
      H.block<6, 6>(0, 0).noalias() += DiS.leftCols<2>() * Di;
      H.block<6, 6>(0, 6).noalias() += DiS.middleCols<2>(2) * Dp;
      H.block<6, 6>(6, 0).noalias() += DpS.leftCols<2>() * Di;
      H.block<6, 6>(6, 6).noalias() += DpS.middleCols<2>(2) * Dp;
      H.block<6, 1>(0, kAlpha) += DiS.col(4);
      H.block<6, 1>(6, kAlpha) += DpS.col(4);
      H.block<1, 6>(kAlpha, 0).noalias() += S.block<1, 2>(4, 0) * Di;
      H.block<1, 6>(kAlpha, 6).noalias() += S.block<1, 2>(4, 2) * Dp;
      H(kAlpha, kAlpha) += S(4, 4);
      g.head<6>().noalias() += Di.transpose() * sr.head<2>();
      g.segment<6>(6).noalias() += Dp.transpose() * sr.segment<2>(2);
      g(kAlpha) += sr(4);
      if (timing_changed) {
        H.block<1, 6>(kConstant, 0).noalias() += s_c.head<2>().transpose() * Di;
        H.block<1, 6>(kConstant, 6).noalias() += s_c.segment<2>(2).transpose() * Dp;
        H(kConstant, kAlpha) += s_c(4);
        H(kConstant, kConstant) += s_cc;
        g(kConstant) += sr_c;
      }
    }
  }
  double haa = H(kAlpha, kAlpha), ga = g(kAlpha);
  if (timing_changed) {
    // c's row was summed alone; its column mirrors it.
    H.block<12, 1>(0, kConstant) = H.block<1, 12>(kConstant, 0).transpose();
    H(kAlpha, kConstant) = H(kConstant, kAlpha);
    eliminate_nuisance<13>(H, g, haa, ga);
  } else {
    eliminate_nuisance<12>(H, g, haa, ga);
  }
  // A frame whose pairs carry less than noise may leave haa negative: its sums still count,
  // or dropping such frames would bias the sum of the others.
  if (!std::isfinite(haa) || !std::isfinite(ga) || !(haa + noise_bb > 0)) return;
  // What is left: alpha's information and its least-squares point (without the elimination
  // and the noise correction these are sbb = sum w B^2 and sab = sum w A B).
  const double sbb = haa, sab = alpha_now * haa - ga;
  est.sab = kForget * est.sab + sab;
  est.sbb = kForget * est.sbb + sbb;
  est.sbb_total = kForget * est.sbb_total + sbb + noise_bb;
  est.sbbr = kForget * est.sbbr + sbb * readout;
  est.scatter_aa = kForget * kForget * est.scatter_aa + sab * sab;
  est.scatter_ab = kForget * kForget * est.scatter_ab + sab * sbb;
  est.scatter_bb = kForget * kForget * est.scatter_bb + sbb * sbb;
  // B^2 sums grow with the square of the frames' intensity scale.
  const double counts2 = double{map.intensity} * map.intensity;
  if (est.sbb < kMinInformation * counts2 || est.sbb < kMinSignalShare * est.sbb_total) return;
  // The starting tau as a weak prior (pseudo-observations with B^2 summing to kPriorWeight).
  const double readout_mean = est.sbbr / est.sbb;
  const double alpha_init = std::exp(-readout_mean / static_cast<double>(map.cfg.tau_init_s));
  const double alpha = (est.sab + kPriorWeight * counts2 * alpha_init) / (est.sbb + kPriorWeight * counts2);
  // A physical range: 1 ms .. 100 ms.
  const double lo = std::exp(-readout_mean / 0.001), hi = std::exp(-readout_mean / 0.1);
  const double a = std::max(lo, std::min(hi, alpha));
  const double tau = -readout_mean / std::log(a);
  if (!std::isfinite(tau)) return;
  est.tau.c = est.tau.h = tau;
  est.solved = true;
}

double tau_standard_error(const TauEstimator& est) {
  // The events' mean weighs the latest as much as all before: for independent measurements its
  // variance is a third of theirs.
  if (est.shutter_measurements > 0) return est.shutter_measurements >= 2 ? std::sqrt(est.shutter_tau_var / 3) : 0.0;
  if (!est.solved || !(est.sbb > 0) || !(est.sbbr > 0)) return 0.0;
  // alpha = sab / sbb over frames f: var(alpha) = sum_f (sab_f - alpha sbb_f)^2 / sbb^2, each
  // frame's terms forgotten as in the sums; then through tau = -t_r / ln(alpha).
  const double alpha = est.sab / est.sbb;
  const double scatter = est.scatter_aa - 2 * alpha * est.scatter_ab + alpha * alpha * est.scatter_bb;
  if (!(alpha > 0 && alpha < 1) || !(scatter > 0)) return 0.0;
  const double alpha_se = std::sqrt(scatter) / est.sbb;
  const double log_alpha = std::log(alpha);
  const double readout_mean = est.sbbr / est.sbb;
  return alpha_se * readout_mean / (alpha * log_alpha * log_alpha);
}

}  // namespace bolo::vo
