// Sliding-window photometric bundle adjustment, run at every new keyframe: the poses and affine
// brightness of the window's keyframes and the inverse depths of their active points minimise
// the robust photometric error of every point in every other keyframe of the window. The points
// are eliminated by the Schur complement (each inverse depth couples only to the keyframe
// parameters), Levenberg-Marquardt on the reduced system. The oldest keyframe fixes the gauge;
// brightness parameters are held unless the mode is `affine`. Retired keyframes are dropped
// without a marginalisation prior.

#include <cmath>

#include <Eigen/Cholesky>

#include "state.hpp"

namespace bolo::vo {
namespace {

constexpr int kIterations = 4;

struct Totals {
  double energy = 0;
  std::uint32_t blocks = 0, inliers = 0;
};

// Index of each window keyframe's parameter block, by slot.
struct Window {
  int index[kMaxKeyframes];
  std::uint32_t count = 0;
};

Window window_of(const State& s) {
  Window w;
  for (auto& i : w.index) i = -1;
  for (std::uint32_t k = 0; k < s.kf_count; ++k) w.index[s.order[k]] = static_cast<int>(k);
  w.count = s.kf_count;
  return w;
}

// drop_outliers: points that fit most of the keyframes they are seen in badly are marked `leaving`.
Totals accumulate(State& s, const Window& win, bool with_jacobians, bool drop_outliers) {
  Totals tot;
  const Scaled k = camera_at(s.cfg.camera, 0);
  const float hub = s.cfg.huber_counts, c2 = s.cfg.gradient_c * s.cfg.gradient_c;
  const float cutoff = kPattern * hub * hub * 6.0f;
  const std::uint32_t n = 8 * win.count;
  if (with_jacobians) {
    s.ba_H.setZero();
    s.ba_b.setZero();
  }
  // Relative poses and brightness gains of every (host, target) pair, once per pass.
  Se3 pair_M[kMaxKeyframes][kMaxKeyframes];
  double pair_e[kMaxKeyframes][kMaxKeyframes];
  for (std::uint32_t hs = 0; hs < kMaxKeyframes; ++hs)
    for (std::uint32_t ts = 0; ts < kMaxKeyframes; ++ts)
      if (s.kf[hs].used && s.kf[ts].used && ts != hs) {
        pair_M[hs][ts] = s.kf[ts].T_cw * s.kf[hs].T_cw.inverse();
        pair_e[hs][ts] = std::exp(s.kf[ts].a - s.kf[hs].a);
      }
  std::uint32_t point_index = 0;
  for (std::uint32_t hs = 0; hs < kMaxKeyframes; ++hs) {
    Keyframe& host = s.kf[hs];
    if (!host.used) continue;
    const int hi = win.index[hs];
    for (std::uint32_t i = 0; i < host.count; ++i) {
      Point& p = host.points[i];
      if (p.status != PointStatus::active) continue;
      float* row = s.ba_hxr.data() + std::size_t{point_index} * kBaStride;
      s.ba_index[point_index++] = hs << 16 | i;
      // An energy-only pass leaves the rows alone.
      if (with_jacobians) {
        for (std::uint32_t q = 0; q < n; ++q) row[3 + q] = 0;
        row[0] = row[1] = 0;
      }
      const Eigen::Vector3d nv((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d Xh = nv / p.idepth;
      // The host's pattern: the same for every target.
      float refv[kPattern];
      for (std::uint32_t j = 0; j < kPattern; ++j)
        refv[j] = bilinear(host.pyramid.level[0].value, p.u + kPatternX[j], p.v + kPatternY[j]);
      std::uint32_t observed = 0, bad = 0;
      for (std::uint32_t ts = 0; ts < kMaxKeyframes; ++ts) {
        const Keyframe& target = s.kf[ts];
        if (!target.used || ts == hs) continue;
        const int ti = win.index[ts];
        const Se3& M = pair_M[hs][ts];
        const Eigen::Vector3d X = M * Xh;
        if (X.z() <= 1e-4) continue;
        const double x = X.x() / X.z(), y = X.y() / X.z();
        const auto u = static_cast<float>(k.fx * x + k.cx), v = static_cast<float>(k.fy * y + k.cy);
        const Level& tl = target.pyramid.level[0];
        if (!inside(tl.value, u, v, 3.0f)) continue;
        ++observed;
        const double e = pair_e[hs][ts];
        float r[kPattern], w[kPattern], gx[kPattern], gy[kPattern];
        float energy = 0;
        for (std::uint32_t j = 0; j < kPattern; ++j) {
          const Sample c = bilinear_with_gradient(tl.value, tl.gx, tl.gy, u + kPatternX[j], v + kPatternY[j]);
          r[j] = static_cast<float>(c.value - (e * (refv[j] - host.b) + target.b));
          const float hw = huber_weight(r[j], hub);
          w[j] = hw * c2 / (c2 + c.gx * c.gx + c.gy * c.gy);
          gx[j] = c.gx, gy[j] = c.gy;
          energy += hw * r[j] * r[j] * (2.0f - hw);
        }
        ++tot.blocks;
        if (energy > cutoff) {
          tot.energy += cutoff;
          ++bad;
          continue;
        }
        ++tot.inliers;
        tot.energy += energy;
        if (!with_jacobians) continue;
        // d(u,v)/dX, then X's derivatives by target pose, host pose and inverse depth.
        Eigen::Matrix<double, 2, 3> P;
        P << k.fx / X.z(), 0, -k.fx * X.x() / (X.z() * X.z()), 0, k.fy / X.z(), -k.fy * X.y() / (X.z() * X.z());
        Eigen::Matrix<double, 3, 6> dT, dH;
        dT << Eigen::Matrix3d::Identity(), -skew(X);
        dH << -M.R, M.R * skew(Xh);
        const Eigen::Matrix<double, 2, 6> Jt = P * dT, Jh = P * dH;
        const Eigen::Vector2d Jr = P * (M.R * (-nv / (static_cast<double>(p.idepth) * p.idepth)));
        // Each pattern pixel's Jacobian row is J_j = K z_j with z_j = (gx, gy, ref - b_host, 1) and K
        // (16 x 4) the same for the whole pattern (host block: Jh^T, e, e; target block: Jt^T,
        // -e, -1), so the pattern adds K Z K^T with Z = sum w z z^T: one 4x4 sum a pixel and one
        // 16x16 product a block instead of four 8x8 outer products a pixel.
        Eigen::Matrix4d Z = Eigen::Matrix4d::Zero();
        Eigen::Vector4d zr = Eigen::Vector4d::Zero();
        for (std::uint32_t j = 0; j < kPattern; ++j) {
          const Eigen::Vector4d z(gx[j], gy[j], refv[j] - host.b, 1.0);
          const double wj = w[j];
          Z.noalias() += (wj * z) * z.transpose();
          zr += (wj * r[j]) * z;
        }
        Eigen::Matrix<double, 16, 4> K = Eigen::Matrix<double, 16, 4>::Zero();
        K.block<6, 2>(0, 0) = Jh.transpose();
        K(6, 2) = e, K(7, 3) = e;
        K.block<6, 2>(8, 0) = Jt.transpose();
        K(14, 2) = -e, K(15, 3) = -1;
        // Coefficient-wise products: at these sizes Eigen's blocked GEMM costs more than it saves.
        const Eigen::Matrix<double, 16, 4> KZ = K.lazyProduct(Z);
        const Eigen::Matrix<double, 16, 16> L = KZ.lazyProduct(K.transpose());
        const Eigen::Matrix<double, 16, 1> bl = K * zr;
        const Eigen::Vector4d jr4(Jr[0], Jr[1], 0.0, 0.0);
        const Eigen::Matrix<double, 16, 1> coupling = KZ * jr4;  // sum w J (g . Jr)
        const int off[2] = {8 * hi, 8 * ti};
        for (int A = 0; A < 2; ++A) {
          for (int B = 0; B < 2; ++B)
            s.ba_H.block<8, 8>(off[A], off[B]) += L.block<8, 8>(Eigen::Index{8} * A, Eigen::Index{8} * B);
          s.ba_b.segment<8>(off[A]) += bl.segment<8>(Eigen::Index{8} * A);
          for (int q = 0; q < 8; ++q) row[3 + off[A] + q] += static_cast<float>(coupling[8 * A + q]);
        }
        row[0] += static_cast<float>(jr4.dot(Z * jr4));
        row[1] += static_cast<float>(jr4.dot(zr));
      }
      if (drop_outliers && observed > 0 && bad * 2 > observed) p.status = PointStatus::leaving;
    }
  }
  return tot;
}

void set_status(State& s, PointStatus from, PointStatus to) {
  for (Keyframe& kf : s.kf)
    if (kf.used)
      for (std::uint32_t i = 0; i < kf.count; ++i)
        if (kf.points[i].status == from) kf.points[i].status = to;
}

}  // namespace

void window_bundle_adjustment(State& s) {
  const Window win = window_of(s);
  // Eigen::Index is int on 32-bit boards: signed loop indices throughout.
  const int n = static_cast<int>(8 * win.count);
  const int total = static_cast<int>(kMaxBaParams);
  const bool affine = s.cfg.photometric == Photometric::affine;
  double lambda = 1e-3;
  bool outliers_marked = false;
  Totals cur = accumulate(s, win, true, false);
  for (int it = 0; it < kIterations && cur.inliers > 0; ++it) {
    BaMatrix& H = s.ba_H;
    BaVector b = s.ba_b;
    std::uint32_t points = 0;
    for (const Keyframe& kf : s.kf)
      if (kf.used)
        for (std::uint32_t i = 0; i < kf.count; ++i) points += kf.points[i].status == PointStatus::active;
    // Schur complement onto the keyframe parameters.
    BaMatrix Hs = H;
    for (std::uint32_t pi = 0; pi < points; ++pi) {
      const float* row = s.ba_hxr.data() + std::size_t{pi} * kBaStride;
      const double hrr = row[0] * (1 + lambda) + 1e-6;
      if (row[0] <= 0) continue;
      // The lower triangle only: LDLT reads nothing else.
      for (int q = 0; q < n; ++q) {
        const double cq = row[3 + q] / hrr;
        if (cq == 0) continue;
        b[q] -= cq * row[1];
        for (int r = 0; r <= q; ++r) Hs(q, r) -= cq * row[3 + r];
      }
    }
    for (int q = 0; q < n; ++q) Hs(q, q) += lambda * H(q, q) + 1e-6;
    for (int q = 0; q < 8; ++q) Hs(q, q) += 1e12;  // gauge: the oldest keyframe
    if (!affine)
      for (int k = 0; k < n / 8; ++k) Hs(8 * k + 6, 8 * k + 6) += 1e12, Hs(8 * k + 7, 8 * k + 7) += 1e12;
    for (int q = n; q < total; ++q) {
      Hs.row(q).setZero(), Hs.col(q).setZero();
      Hs(q, q) = 1, b[q] = 0;
    }
    const BaVector dx = -Hs.ldlt().solve(b);
    if (!dx.allFinite()) break;
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
      float* row = s.ba_hxr.data() + std::size_t{pi} * kBaStride;
      Point& p = s.kf[s.ba_index[pi] >> 16].points[s.ba_index[pi] & 0xffff];
      row[2] = p.idepth;
      if (row[0] <= 0) continue;
      double coupling = 0;
      for (int q = 0; q < n; ++q) coupling += row[3 + q] * dx[q];
      const double d = -(row[1] + coupling) / (row[0] * (1 + lambda) + 1e-6);
      p.idepth = static_cast<float>(std::max(1e-3, std::min(100.0, p.idepth + d)));
    }
    // The trial pass builds the next system as it goes (a step is usually taken); after the last
    // iteration no system is needed, so that trial only sums the energy and marks the outliers
    // (when it is accepted, as it usually is, no pass of its own is needed for them).
    const bool last = it + 1 == kIterations;
    const Totals next = accumulate(s, win, !last, last);
    if (last) outliers_marked = true;
    if (next.energy < cur.energy) {
      lambda = std::max(lambda * 0.5, 1e-6);
      cur = next;
    } else {
      for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot)
        if (s.kf[slot].used) s.kf[slot].T_cw = saved_pose[slot], s.kf[slot].a = saved_a[slot], s.kf[slot].b = saved_b[slot];
      for (std::uint32_t pi = 0; pi < points; ++pi)
        s.kf[s.ba_index[pi] >> 16].points[s.ba_index[pi] & 0xffff].idepth = s.ba_hxr[std::size_t{pi} * kBaStride + 2];
      lambda *= 10;
      if (last) set_status(s, PointStatus::leaving, PointStatus::active), outliers_marked = false;
      // The refused trial overwrote the system: rebuild it at the restored parameters (an
      // energy-only trial leaves it alone).
      if (!last) cur = accumulate(s, win, true, false);
    }
  }
  if (!outliers_marked) accumulate(s, win, false, true);
  set_status(s, PointStatus::leaving, PointStatus::empty);  // points that fit most keyframes badly leave the map
  s.ref_dirty = true;
  // The newest keyframe is the current frame: follow its refined pose.
  const Keyframe& newest = s.kf[s.order[s.kf_count - 1]];
  s.T_cw = newest.T_cw;
  s.a = newest.a, s.b = newest.b;
}

}  // namespace bolo::vo
