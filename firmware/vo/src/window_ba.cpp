// Sliding-window photometric bundle adjustment, run at every new keyframe: the poses and affine
// brightness of the window's keyframes and the inverse depths of their active points minimise
// the robust photometric error of every point in every other keyframe of the window. The points
// are eliminated by the Schur complement (each inverse depth couples only to the keyframe
// parameters), Levenberg-Marquardt on the reduced system. The oldest keyframe fixes the gauge;
// brightness parameters are held unless the mode is `affine`. Retired keyframes are folded
// into a marginalisation prior on the rest: their points' information, the points and then their
// own parameters eliminated (DSO's marginalisation, relinearised at each retirement rather than
// held at first estimates).

#include <cmath>

#include <Eigen/Cholesky>

#include "state.hpp"

namespace bolo::vo {
namespace {

constexpr int kIterations = 4;

// The first of slot (or window place) k's 8 parameters; Eigen::Index is int on 32-bit boards.
Eigen::Index block8(std::uint32_t k) { return 8 * static_cast<Eigen::Index>(k); }

struct Totals {
  double energy = 0;
  std::uint32_t blocks = 0, inliers = 0;
};

// One point's row in s.scratch (kBaStride floats): the point's own Hessian and gradient, a backup
// of its inverse depth, its coupling to every keyframe parameter, its host pattern and counts.
constexpr std::size_t kRowHrr = 0, kRowGr = 1, kRowBackup = 2, kRowCoupling = 3;
constexpr std::size_t kRowRef = kRowCoupling + kMaxBaParams;
constexpr std::size_t kRowObserved = kRowRef + kPattern, kRowBad = kRowObserved + 1;
static_assert(kRowBad < kBaStride, "the BA row layout must fit kBaStride");

// The window of one bundle adjustment: each keyframe's parameter block by slot, and its active
// points (rows first .. first + points - 1 of s.scratch, ba.index naming them), whose host
// patterns are sampled here once: host images and pixels do not change during the adjustment.
struct Window {
  int index[kMaxKeyframes];
  std::uint32_t count = 0;
  std::uint32_t first[kMaxKeyframes] = {}, points_of[kMaxKeyframes] = {};
  std::uint32_t points = 0;
};

Window window_of(MapCore& s, BaSystem& ba) {
  Window w;
  for (auto& i : w.index) i = -1;
  for (std::uint32_t k = 0; k < s.kf_count; ++k) w.index[s.order[k]] = static_cast<int>(k);
  w.count = s.kf_count;
  for (std::uint32_t hs = 0; hs < kMaxKeyframes; ++hs) {
    const Keyframe& host = s.kf[hs];
    w.first[hs] = w.points;
    if (!host.used) continue;
    for (std::uint32_t i = 0; i < host.count; ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active) continue;
      float* row = s.scratch.data() + std::size_t{w.points} * kBaStride;
      ba.index[w.points++] = hs << 16 | i;
      for (std::uint32_t j = 0; j < kPattern; ++j)
        row[kRowRef + j] = bilinear(host.pyramid.level[0].value, p.u + kPatternX[j], p.v + kPatternY[j]);
    }
    w.points_of[hs] = w.points - w.first[hs];
  }
  return w;
}

using Mat8 = Eigen::Matrix<double, 8, 8>;
using Vec8 = Eigen::Matrix<double, 8, 1>;

// Host parameters' Jacobian from the target's for a pair: J_host = J_target * A. The host pose
// enters X = M X_h only through M = T_t T_h^-1, so perturbing the host by d moves M by
// -Adj(M) d; the host's affine a and b enter with -1 and -e where the target's a and b enter.
// This lets a pair sum one 8x8 block per observation and map it to the four blocks once.
Mat8 host_from_target(const Se3& M, double e) {
  Mat8 A = Mat8::Zero();
  A.block<3, 3>(0, 0) = -M.R;
  A.block<3, 3>(0, 3) = -skew(M.t) * M.R;
  A.block<3, 3>(3, 3) = -M.R;
  A(6, 6) = -1;
  A(7, 7) = -e;
  return A;
}

// A^T c for A = host_from_target(): its nonzero blocks only.
Vec8 host_coupling_from_target(const Mat8& A, const Vec8& c) {
  Vec8 h;
  h.head<3>() = A.block<3, 3>(0, 0).transpose() * c.head<3>();
  h.segment<3>(3) = A.block<3, 3>(0, 3).transpose() * c.head<3>() + A.block<3, 3>(3, 3).transpose() * c.segment<3>(3);
  h[6] = A(6, 6) * c[6], h[7] = A(7, 7) * c[7];
  return h;
}

// The distinct entries of Z = sum w z z^T and of sum w r z over a pattern, z = (gx, gy, a, 1)
// (a: the host's pattern value less its offset), summed four pattern pixels at a time.
struct PatternSums {
  double xx = 0, xy = 0, yy = 0, xa = 0, ya = 0, x1 = 0, y1 = 0, aa = 0, a1 = 0, ones = 0;
  double rx = 0, ry = 0, ra = 0, r1 = 0;
};

PatternSums pattern_sums(const float* w, const float* gx, const float* gy, const float* host_values, float host_b,
                         const float* r) {
  using V = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
  Eigen::Array4f xx = Eigen::Array4f::Zero(), xy = xx, yy = xx, xa = xx, ya = xx, x1 = xx, y1 = xx;
  Eigen::Array4f aa = xx, a1 = xx, ones = xx, rx = xx, ry = xx, ra = xx, r1 = xx;
  for (std::uint32_t h = 0; h < kPattern; h += 4) {
    const Eigen::Array4f wh = V(w + h), gxh = V(gx + h), gyh = V(gy + h), rh = V(r + h);
    const Eigen::Array4f a = Eigen::Map<const Eigen::Array4f>(host_values + h) - host_b;
    const Eigen::Array4f wx = wh * gxh, wy = wh * gyh, wa = wh * a;
    xx += wx * gxh, xy += wx * gyh, yy += wy * gyh;
    xa += wx * a, ya += wy * a, x1 += wx, y1 += wy;
    aa += wa * a, a1 += wa, ones += wh;
    rx += wx * rh, ry += wy * rh, ra += wa * rh, r1 += wh * rh;
  }
  return {xx.sum(), xy.sum(), yy.sum(), xa.sum(), ya.sum(), x1.sum(), y1.sum(), aa.sum(), a1.sum(), ones.sum(),
          rx.sum(),  ry.sum(), ra.sum(), r1.sum()};
}

// drop_outliers: points that fit most of the keyframes they are seen in badly are marked `leaving`.
// Pair by pair (host, target), so each pass walks one target image at a time. only_host >= 0:
// the points of that slot only.
Totals accumulate(MapCore& s, BaSystem& ba, const Window& win, bool with_jacobians, bool drop_outliers, int only_host = -1) {
  Totals tot;
  const Scaled k = camera_at(s.cfg.camera, 0);
  const float hub = huber_threshold(s), c2 = gradient_weight_c(s) * gradient_weight_c(s);
  const float cutoff = kPattern * hub * hub * 6.0f;
  if (with_jacobians) {
    ba.H.setZero();
    ba.b.setZero();
  }
  for (std::uint32_t pi = 0; pi < win.points; ++pi) {
    float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
    // An energy-only pass leaves the system rows alone.
    if (with_jacobians)
      for (std::size_t q = 0; q < kRowRef; ++q)
        if (q != kRowBackup) row[q] = 0;
    row[kRowObserved] = row[kRowBad] = 0;
  }
  for (std::uint32_t hs = 0; hs < kMaxKeyframes; ++hs) {
    const Keyframe& host = s.kf[hs];
    if (!host.used || win.points_of[hs] == 0) continue;
    if (only_host >= 0 && hs != static_cast<std::uint32_t>(only_host)) continue;
    const int hi = win.index[hs];
    for (std::uint32_t ts = 0; ts < kMaxKeyframes; ++ts) {
      const Keyframe& target = s.kf[ts];
      if (!target.used || ts == hs) continue;
      const int ti = win.index[ts];
      const Se3 M = target.T_cw * host.T_cw.inverse();
      const double e = std::exp(target.a - host.a);
      const Mat8 A = host_from_target(M, e);
      const Mat8 At = A.transpose();
      const Level& tl = target.pyramid.level[0];
      Mat8 pair_H = Mat8::Zero();
      Vec8 pair_b = Vec8::Zero();
      const std::uint32_t end = win.first[hs] + win.points_of[hs];
      for (std::uint32_t pi = win.first[hs]; pi < end; ++pi) {
        float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
        const Point& p = host.points[ba.index[pi] & 0xffff];
        const Eigen::Vector3d nv((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0);
        const Eigen::Vector3d X = M * (nv / p.idepth);
        if (X.z() <= 1e-4) continue;
        const double x = X.x() / X.z(), y = X.y() / X.z();
        const auto u = static_cast<float>(k.fx * x + k.cx), v = static_cast<float>(k.fy * y + k.cy);
        if (!inside(tl.value, u, v, 3.0f)) continue;
        row[kRowObserved] += 1;
        const float* refv = row + kRowRef;
        alignas(16) float value[kPattern], gx[kPattern], gy[kPattern], r[kPattern], w[kPattern];
        for (std::uint32_t j = 0; j < kPattern; ++j) {
          const Sample c = bilinear_with_gradient(tl.value, tl.gx, tl.gy, u + kPatternX[j], v + kPatternY[j]);
          value[j] = c.value, gx[j] = c.gx, gy[j] = c.gy;
        }
        const auto hb = static_cast<float>(host.b);
        const float energy = pattern_residuals(value, gx, gy, refv, static_cast<float>(e), hb, static_cast<float>(target.b), hub, c2, r, w);
        ++tot.blocks;
        if (energy > cutoff) {
          tot.energy += cutoff;
          row[kRowBad] += 1;
          continue;
        }
        ++tot.inliers;
        tot.energy += energy;
        if (!with_jacobians) continue;
        // d(u,v)/dX, then X's derivatives by the target pose and the inverse depth.
        Eigen::Matrix<double, 2, 3> P;
        P << k.fx / X.z(), 0, -k.fx * X.x() / (X.z() * X.z()), 0, k.fy / X.z(), -k.fy * X.y() / (X.z() * X.z());
        Eigen::Matrix<double, 3, 6> dT;
        dT << Eigen::Matrix3d::Identity(), -skew(X);
        const Eigen::Matrix<double, 2, 6> Jt = P * dT;
        const Eigen::Vector2d Jr = P * (M.R * (-nv / (static_cast<double>(p.idepth) * p.idepth)));
        // Each pattern pixel's Jacobian row (target parameters) is J_j = K z_j with
        // z_j = (gx, gy, ref - b_host, 1) and K (8 x 4: Jt^T, -e, -1) the same for the whole
        // pattern, so the pattern adds K Z K^T with Z = sum w z z^T. K is block-diagonal (the
        // pose rows see only the gradient, a and b one column each), and the products below are
        // written per block: a dense 8x4 by 4x8 product was most of the adjustment's time.
        const PatternSums z = pattern_sums(w, gx, gy, refv, hb, r);
        double m0[6], m1[6];  // Z's gradient block times Jt
        for (int q = 0; q < 6; ++q) {
          m0[q] = z.xx * Jt(0, q) + z.xy * Jt(1, q);
          m1[q] = z.xy * Jt(0, q) + z.yy * Jt(1, q);
        }
        for (int q = 0; q < 6; ++q) {
          for (int c = q; c < 6; ++c) pair_H(q, c) += Jt(0, q) * m0[c] + Jt(1, q) * m1[c];
          pair_H(q, 6) -= e * (Jt(0, q) * z.xa + Jt(1, q) * z.ya);
          pair_H(q, 7) -= Jt(0, q) * z.x1 + Jt(1, q) * z.y1;
          pair_b[q] += Jt(0, q) * z.rx + Jt(1, q) * z.ry;
        }
        pair_H(6, 6) += e * e * z.aa, pair_H(6, 7) += e * z.a1, pair_H(7, 7) += z.ones;
        pair_b[6] -= e * z.ra, pair_b[7] -= z.r1;
        // The point's coupling: sum w J (g . Jr), for the target's parameters and, through A,
        // the host's.
        const double zj0 = z.xx * Jr[0] + z.xy * Jr[1], zj1 = z.xy * Jr[0] + z.yy * Jr[1];
        const double zj2 = z.xa * Jr[0] + z.ya * Jr[1], zj3 = z.x1 * Jr[0] + z.y1 * Jr[1];
        Vec8 coupling_t;
        for (int q = 0; q < 6; ++q) coupling_t[q] = Jt(0, q) * zj0 + Jt(1, q) * zj1;
        coupling_t[6] = -e * zj2, coupling_t[7] = -zj3;
        const Vec8 coupling_h = host_coupling_from_target(A, coupling_t);
        float* target_coupling = row + kRowCoupling + 8 * static_cast<std::size_t>(ti);
        float* host_coupling = row + kRowCoupling + 8 * static_cast<std::size_t>(hi);
        for (int q = 0; q < 8; ++q) {
          target_coupling[q] += static_cast<float>(coupling_t[q]);
          host_coupling[q] += static_cast<float>(coupling_h[q]);
        }
        row[kRowHrr] += static_cast<float>(Jr[0] * zj0 + Jr[1] * zj1);
        row[kRowGr] += static_cast<float>(Jr[0] * z.rx + Jr[1] * z.ry);
      }
      if (!with_jacobians) continue;
      pair_H = pair_H.selfadjointView<Eigen::Upper>();
      const Mat8 HA = pair_H * A;
      const Eigen::Index t0 = Eigen::Index{8} * ti, h0 = Eigen::Index{8} * hi;
      ba.H.block<8, 8>(t0, t0) += pair_H;
      ba.H.block<8, 8>(t0, h0) += HA;
      ba.H.block<8, 8>(h0, t0) += HA.transpose();
      ba.H.block<8, 8>(h0, h0) += At * HA;
      ba.b.segment<8>(t0) += pair_b;
      ba.b.segment<8>(h0) += At * pair_b;
    }
  }
  if (drop_outliers)
    for (std::uint32_t pi = 0; pi < win.points; ++pi) {
      const float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
      if (row[kRowObserved] > 0 && row[kRowBad] * 2 > row[kRowObserved])
        s.kf[ba.index[pi] >> 16].points[ba.index[pi] & 0xffff].status = PointStatus::leaving;
    }
  return tot;
}

// The prior evaluated at the current parameters. A quadratic prior is not invariant to the
// scale of a monocular window: with its linearisation point x0 in its null space, the window
// scaled by k about x0's shape costs k^2 (x - x0)^T H (x - x0) and is pulled towards scale 0
// (the map shrinks within seconds). So it is read in the linearisation's scale:
// the linearisation point's camera centres are scaled by the ratio k of the current spread to
// theirs (about the current centroid), and translation offsets are divided by k (D = diag(1/k)).
struct PriorAtCurrent {
  BaVector d = BaVector::Zero();  // D times the offsets, by slot
  double inv_scale = 1;           // 1/k: D's translation entries
};

Vec3 camera_centre(const Se3& T_cw) { return -(T_cw.R.transpose() * T_cw.t); }

PriorAtCurrent prior_at_current(const MapCore& s, const MarginalPrior& prior) {
  PriorAtCurrent out;
  Vec3 centroid_now = Vec3::Zero(), centroid_lin = Vec3::Zero();
  Vec3 centre_now[kMaxKeyframes], centre_lin[kMaxKeyframes];
  int n = 0;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    if (!s.kf[slot].used || !prior.in_prior[slot]) continue;
    const Se3& now = s.kf[slot].T_cw;
    const Se3& lin = prior.T_cw[slot];
    centre_now[slot] = camera_centre(now), centre_lin[slot] = camera_centre(lin);
    centroid_now += centre_now[slot], centroid_lin += centre_lin[slot], ++n;
  }
  double spread_now = 0, spread_lin = 0;
  if (n > 0) {
    centroid_now /= n, centroid_lin /= n;
    for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot)
      if (s.kf[slot].used && prior.in_prior[slot])
        spread_now += (centre_now[slot] - centroid_now).squaredNorm(), spread_lin += (centre_lin[slot] - centroid_lin).squaredNorm();
  }
  const double k = n >= 2 && spread_lin > 0 && spread_now > 0 ? std::sqrt(spread_now / spread_lin) : 1.0;
  out.inv_scale = 1 / k;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    if (!s.kf[slot].used || !prior.in_prior[slot]) continue;
    const Keyframe& kf = s.kf[slot];
    Se3 lin = prior.T_cw[slot];
    if (n >= 2) lin.t = -(lin.R * (centroid_now + k * (centre_lin[slot] - centroid_lin)));
    Vec8 d;
    d.head<6>() = (kf.T_cw * lin.inverse()).log();
    d.head<3>() *= out.inv_scale;
    d[6] = kf.a - prior.a[slot], d[7] = kf.b - prior.b_offset[slot];
    out.d.segment<8>(block8(slot)) = d;
  }
  return out;
}

// D as a vector, by slot.
BaVector prior_scaling(double inv_scale) {
  BaVector D = BaVector::Ones();
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) D.segment<3>(block8(slot)).setConstant(inv_scale);
  return D;
}

// The prior's half-gradient D (b + H d) by slot, and its energy in the photometric energy's
// units (twice the quadratic model).
BaVector prior_gradient(const MarginalPrior& prior, const PriorAtCurrent& at) {
  return prior_scaling(at.inv_scale).cwiseProduct(prior.b + prior.H * at.d);
}
double prior_energy(const MarginalPrior& prior, const PriorAtCurrent& at) {
  return 2 * prior.b.dot(at.d) + at.d.dot(prior.H * at.d);
}

// The current window's scale direction in window order (left increments; the oldest keyframe,
// the BA's gauge, stays), normalised: the prior must neither push nor hold along it.
BaVector scale_direction(const MapCore& s) {
  BaVector v = BaVector::Zero();
  const Se3& oldest = s.kf[s.order[0]].T_cw;
  const Vec3 c0 = camera_centre(oldest);
  for (std::uint32_t k = 1; k < s.kf_count; ++k) {
    const Se3& T = s.kf[s.order[k]].T_cw;
    v.segment<3>(block8(k)) = -(T.R * (camera_centre(T) - c0));
  }
  const double norm = v.norm();
  return norm > 0 ? BaVector(v / norm) : v;
}

// The prior read at the current parameters and the window's scale direction there: what the
// prior's Hessian and gradient in window order are made from.
struct PriorInWindow {
  PriorAtCurrent at;
  BaVector scale_dir = BaVector::Zero();
};
PriorInWindow prior_in_window(const MapCore& s, const MarginalPrior& prior) {
  PriorInWindow p;
  if (prior.set) p.at = prior_at_current(s, prior), p.scale_dir = scale_direction(s);
  return p;
}

// The prior's Hessian D H D in window order (the BA's parameter layout).
void prior_hessian_in_window(const MarginalPrior& prior, const Window& win, const PriorInWindow& p, BaMatrix& H) {
  H.setZero();
  if (!prior.set) return;
  const BaVector D = prior_scaling(p.at.inv_scale);
  const BaMatrix DHD = D.asDiagonal() * prior.H * D.asDiagonal();
  for (std::uint32_t si = 0; si < kMaxKeyframes; ++si) {
    if (win.index[si] < 0) continue;
    for (std::uint32_t sj = 0; sj < kMaxKeyframes; ++sj)
      if (win.index[sj] >= 0)
        H.block<8, 8>(Eigen::Index{8} * win.index[si], Eigen::Index{8} * win.index[sj]) =
            DHD.block<8, 8>(block8(si), block8(sj));
  }
  const BaVector& v = p.scale_dir;
  const BaVector Hv = H * v;
  H -= Hv * v.transpose() + v * Hv.transpose() - v.dot(Hv) * v * v.transpose();  // P H P
}

// The prior's half-gradient at the current parameters in window order; returns its energy.
double prior_gradient_in_window(const MarginalPrior& prior, const Window& win, const PriorInWindow& p, BaVector& b) {
  b.setZero();
  if (!prior.set) return 0;
  const BaVector g = prior_gradient(prior, p.at);
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot)
    if (win.index[slot] >= 0) b.segment<8>(Eigen::Index{8} * win.index[slot]) = g.segment<8>(block8(slot));
  b -= p.scale_dir.dot(b) * p.scale_dir;
  return prior_energy(prior, p.at);
}

void set_status(MapCore& s, PointStatus from, PointStatus to) {
  for (Keyframe& kf : s.kf)
    if (kf.used)
      for (std::uint32_t i = 0; i < kf.count; ++i)
        if (kf.points[i].status == from) kf.points[i].status = to;
}

}  // namespace

double window_system(MapCore& s, BaSystem& ba) { return accumulate(s, ba, window_of(s, ba), true, false).energy; }

double marginal_prior_energy(const MapCore& s, const MarginalPrior& prior) {
  return prior.set ? prior_energy(prior, prior_at_current(s, prior)) : 0.0;
}

void clear_marginal_prior(MarginalPrior& prior) {
  for (bool& in : prior.in_prior) in = false;
  prior.H.setZero();
  prior.b.setZero();
  prior.set = false;
}

void marginalise_oldest_keyframe(MapCore& s, BaSystem& ba, MarginalPrior& prior) {
  if (s.kf_count < 2) return;
  const std::uint32_t old = s.order[0];
  const Window win = window_of(s, ba);
  const int n = static_cast<int>(8 * win.count);
  const bool affine = s.cfg.photometric == Photometric::affine;
  accumulate(s, ba, win, true, false, static_cast<int>(old));
  // Eliminate the retiring keyframe's points from their observations' system.
  BaMatrix& H = ba.H;
  BaVector& b = ba.b;
  const std::uint32_t end = win.first[old] + win.points_of[old];
  for (std::uint32_t pi = win.first[old]; pi < end; ++pi) {
    const float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
    if (row[kRowHrr] <= 0) continue;
    const double hrr = row[kRowHrr] + 1e-6;
    const float* coupling = row + kRowCoupling;
    for (int q = 0; q < n; ++q) {
      const double cq = coupling[q] / hrr;
      if (cq == 0) continue;
      b[q] -= cq * row[kRowGr];
      for (int r = q; r < n; ++r) H(r, q) -= cq * coupling[r];
    }
  }
  H = H.selfadjointView<Eigen::Lower>();
  // Move the prior's linearisation point to the current parameters, then add the new terms
  // (window order to slots).
  if (prior.set) {
    const PriorAtCurrent at = prior_at_current(s, prior);
    const BaVector D = prior_scaling(at.inv_scale);
    prior.b = prior_gradient(prior, at);
    prior.H = D.asDiagonal() * prior.H * D.asDiagonal();
  }
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    const Keyframe& kf = s.kf[slot];
    prior.in_prior[slot] = kf.used && slot != old;
    if (kf.used) prior.T_cw[slot] = kf.T_cw, prior.a[slot] = kf.a, prior.b_offset[slot] = kf.b;
  }
  for (std::uint32_t si = 0; si < kMaxKeyframes; ++si) {
    if (win.index[si] < 0) continue;
    const Eigen::Index wi = Eigen::Index{8} * win.index[si], pi = block8(si);
    prior.b.segment<8>(pi) += b.segment<8>(wi);
    for (std::uint32_t sj = 0; sj < kMaxKeyframes; ++sj)
      if (win.index[sj] >= 0)
        prior.H.block<8, 8>(pi, block8(sj)) += H.block<8, 8>(wi, Eigen::Index{8} * win.index[sj]);
  }
  // Brightness parameters the mode holds carry no information.
  if (!affine)
    for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot)
      for (Eigen::Index q = block8(slot) + 6; q < block8(slot) + 8; ++q)
        prior.H.row(q).setZero(), prior.H.col(q).setZero(), prior.b[q] = 0;
  // Eliminate the retiring keyframe's own parameters.
  const Eigen::Index o = block8(old), m = affine ? 8 : 6;
  Eigen::Matrix<double, 8, 8> Hoo = prior.H.block<8, 8>(o, o);
  for (Eigen::Index q = 0; q < m; ++q) Hoo(q, q) += 1e-9 * (1 + Hoo(q, q));
  for (Eigen::Index q = m; q < 8; ++q) Hoo(q, q) = 1;
  const Eigen::LDLT<Eigen::Matrix<double, 8, 8>> Hoo_ldlt(Hoo);
  const Eigen::Matrix<double, 8, kMaxBaParams> Hor = prior.H.middleRows<8>(o);
  const Eigen::Matrix<double, 8, kMaxBaParams> X = Hoo_ldlt.solve(Hor);
  const Eigen::Matrix<double, 8, 1> y = Hoo_ldlt.solve(prior.b.segment<8>(o));
  if (X.allFinite() && y.allFinite()) {
    prior.H.noalias() -= Hor.transpose() * X;
    prior.b.noalias() -= Hor.transpose() * y;
  }
  prior.H.middleRows<8>(o).setZero(), prior.H.middleCols<8>(o).setZero(), prior.b.segment<8>(o).setZero();
  prior.H = (0.5 * (prior.H + prior.H.transpose())).eval();
  prior.set = true;
}

void window_bundle_adjustment(MapCore& s, BaSystem& ba, const MarginalPrior& prior, TrackingReference& ref) {
  const Window win = window_of(s, ba);
  // Eigen::Index is int on 32-bit boards: signed loop indices throughout.
  const int n = static_cast<int>(8 * win.count);
  const bool affine = s.cfg.photometric == Photometric::affine;
  double lambda = 1e-3;
  bool outliers_marked = false;
  BaMatrix& prior_H = ba.prior_H;
  const PriorInWindow prior_at_start = prior_in_window(s, prior);
  prior_hessian_in_window(prior, win, prior_at_start, prior_H);
  BaVector prior_b;
  Totals cur = accumulate(s, ba, win, true, false);
  double prior_energy = prior_gradient_in_window(prior, win, prior_at_start, prior_b);
  cur.energy += prior_energy;
  // The parameters the adjustment moves, in window order: every keyframe's pose but the oldest's
  // (the gauge) and, in affine only, the brightness. Held parameters stay out of the reduced system
  // (most of the adjustment's own time is the Schur complement, quadratic in its size).
  int moved[kMaxBaParams];
  int m = 0;
  for (int k = 1; k < n / 8; ++k)
    for (int q = 0; q < (affine ? 8 : 6); ++q) moved[m++] = 8 * k + q;
  for (int it = 0; it < kIterations && cur.inliers > 0; ++it) {
    BaMatrix& H = ba.H;
    if (prior.set) H += prior_H;
    const BaVector b_full = ba.b + prior_b;
    const std::uint32_t points = win.points;
    // Schur complement onto the moved keyframe parameters, in their compact order.
    BaMatrix Hs = BaMatrix::Identity();  // the rows past m stay the identity, their steps 0
    BaVector b = BaVector::Zero();
    for (int i = 0; i < m; ++i) {
      b[i] = b_full[moved[i]];
      for (int j = i; j < m; ++j) Hs(j, i) = H(moved[j], moved[i]);
    }
    for (std::uint32_t pi = 0; pi < points; ++pi) {
      const float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
      if (row[kRowHrr] <= 0) continue;
      const double hrr = row[kRowHrr] * (1 + lambda) + 1e-6;
      double c[kMaxBaParams];
      const float* coupling = row + kRowCoupling;
      for (int i = 0; i < m; ++i) c[i] = coupling[moved[i]];
      // The lower triangle only (LDLT reads nothing else), a column at a time: contiguous.
      for (int i = 0; i < m; ++i) {
        const double ci = c[i] / hrr;
        if (ci == 0) continue;
        b[i] -= ci * row[kRowGr];
        for (int j = i; j < m; ++j) Hs(j, i) -= ci * c[j];
      }
    }
    for (int i = 0; i < m; ++i) Hs(i, i) += lambda * H(moved[i], moved[i]) + 1e-6;
    const BaVector reduced_dx = -Hs.ldlt().solve(b);
    if (!reduced_dx.allFinite()) break;
    BaVector dx = BaVector::Zero();
    for (int i = 0; i < m; ++i) dx[moved[i]] = reduced_dx[i];
    // Apply, keeping what is needed to undo.
    Se3 saved_pose[kMaxKeyframes];
    double saved_a[kMaxKeyframes], saved_b[kMaxKeyframes];
    for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
      Keyframe& kf = s.kf[slot];
      if (!kf.used) continue;
      const int idx = win.index[slot];
      saved_pose[slot] = kf.T_cw, saved_a[slot] = kf.a, saved_b[slot] = kf.b;
      kf.T_cw = (Se3::exp(dx.segment<6>(Eigen::Index{8} * idx)) * kf.T_cw).orthonormalised();
      kf.a += dx[8 * idx + 6], kf.b += dx[8 * idx + 7];
    }
    for (std::uint32_t pi = 0; pi < points; ++pi) {
      float* row = s.scratch.data() + std::size_t{pi} * kBaStride;
      Point& p = s.kf[ba.index[pi] >> 16].points[ba.index[pi] & 0xffff];
      row[kRowBackup] = p.idepth;
      if (row[kRowHrr] <= 0) continue;
      double coupling = 0;
      const float* point_coupling = row + kRowCoupling;
      for (int i = 0; i < m; ++i) coupling += point_coupling[moved[i]] * reduced_dx[i];
      const double d = -(row[kRowGr] + coupling) / (row[kRowHrr] * (1 + lambda) + 1e-6);
      p.idepth = static_cast<float>(std::max(1e-3, std::min(100.0, p.idepth + d)));
    }
    // The trial pass builds the next system as it goes (a step is usually taken); after the last
    // iteration no system is needed, so that trial only sums the energy and marks the outliers
    // (when it is accepted, as it usually is, no pass of its own is needed for them).
    const bool last = it + 1 == kIterations;
    Totals next = accumulate(s, ba, win, !last, last);
    BaVector next_prior_b;
    const double next_prior_energy = prior_gradient_in_window(prior, win, prior_in_window(s, prior), next_prior_b);
    next.energy += next_prior_energy;
    if (last) outliers_marked = true;
    if (next.energy < cur.energy) {
      lambda = std::max(lambda * 0.5, 1e-6);
      cur = next;
      prior_b = next_prior_b, prior_energy = next_prior_energy;
    } else {
      for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot)
        if (s.kf[slot].used) s.kf[slot].T_cw = saved_pose[slot], s.kf[slot].a = saved_a[slot], s.kf[slot].b = saved_b[slot];
      for (std::uint32_t pi = 0; pi < points; ++pi)
        s.kf[ba.index[pi] >> 16].points[ba.index[pi] & 0xffff].idepth = s.scratch[std::size_t{pi} * kBaStride + kRowBackup];
      lambda *= 10;
      if (last) set_status(s, PointStatus::leaving, PointStatus::active), outliers_marked = false;
      // The refused trial overwrote the system: rebuild it at the restored parameters (an
      // energy-only trial leaves it alone).
      if (!last) cur = accumulate(s, ba, win, true, false), cur.energy += prior_energy;
    }
  }
  if (!outliers_marked) accumulate(s, ba, win, false, true);
  set_status(s, PointStatus::leaving, PointStatus::empty);  // points that fit most keyframes badly leave the map
  ref.dirty = true;
}

}  // namespace bolo::vo
