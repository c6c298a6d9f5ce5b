// Frame-to-keyframe-window direct alignment: the pose (SE(3)) and brightness parameters of the
// new frame minimise the Huber- and gradient-weighted photometric error of every active point of
// the window, reprojected into the newest keyframe (the tracking reference, as DSO's coarse
// tracker does), coarse to fine over the pyramid, by Levenberg-Marquardt.

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "tracker.hpp"

#include "frame_state.hpp"
#include "map.hpp"
#include "photometric_math.hpp"
#include "scale_bridge.hpp"

namespace bolo::vo {
namespace {

constexpr double kMotionPrior = 0.02;
constexpr double kConverged = 0.003;  // a level stops when a step gains less than this share
constexpr std::uint32_t kRefusedStepsToStop = 2;  // at the finest level (see track_frame)
// A step that moves the points by less than this (in the level's pixels) ends the level.
constexpr double kNegligibleStep = 0.1;
constexpr double kNegligibleGainStep = 1e-3;  // log gain
constexpr std::uint32_t kPixelsPerTrackedPoint = 40;  // share of each translation axis' own information

using Mat8 = Eigen::Matrix<double, 8, 8>;
using Vec8 = Eigen::Matrix<double, 8, 1>;

struct Accumulated {
  Mat8 H = Mat8::Zero();
  Vec8 g = Vec8::Zero();
  double energy = 0;       // robust, over inlier points
  double squared = 0;      // plain squared residuals of inliers (passes without Jacobians: the rms)
  std::uint32_t residuals = 0, visible = 0, inliers = 0;
};

// One pass over the tracking reference (the window's active points reprojected into the newest
// keyframe, whose image supplies the patterns: the nearest keyframe looks most like the frame,
// while an older host's pattern is zoomed and sheared against it, which biased the coarse levels)
// at `level` for the pose T_cw; `cutoff` is the per-point
// pattern energy above which a point counts as an outlier for this pass. `select_view`: this
// pose starts the level, and the points it sees are the level's point set: a point of the set
// that a step moves out of the view costs the cutoff (no step gains by pushing points out), a
// point outside the set costs nothing (no step gains by pulling points in, which would bias
// forward motion backwards, towards the poses that keep the most points in view).
Accumulated accumulate(TrackingReference& reference, MapCore& map, const CurrentFrame& f, std::uint32_t level,
                       const Se3& T_cw, double a, double b, float cutoff, bool with_jacobians, bool mark_inliers,
                       bool select_view = false) {
  Accumulated acc;
  const Level& cur = f.frame.level[level];
  const TexelImage& texels = f.frame_texels[level];
  const Scaled k = camera_at(map.cfg.camera, level);
  const Scaled k0 = camera_at(map.cfg.camera, 0);
  const float scale = 1.0f / static_cast<float>(1u << level);
  const float hub = huber_threshold(map), c2 = gradient_weight_c(map) * gradient_weight_c(map);
  if (map.kf_count == 0) return acc;
  const Keyframe& host = map.kf[map.order[map.kf_count - 1]];
  const Se3 M = T_cw * host.T_cw.inverse();
  const Eigen::Matrix3f R = M.R.cast<float>();
  const Eigen::Vector3f t = M.t.cast<float>();
  const Level& ref = host.pyramid.level[level];
  const float gain = static_cast<float>(std::exp(a - host.a));
  const float hb = static_cast<float>(host.b), fb = static_cast<float>(b);
  if (mark_inliers)
    for (const Keyframe& kf : map.kf)
      if (kf.used)
        for (std::uint32_t i = 0; i < kf.count; ++i) kf.points[i].inlier = false;
  for (std::uint32_t i = 0; i < reference.count; ++i) {
    RefPoint& p = reference.points[i];
    if (!select_view && !p.in_view) continue;
    const Eigen::Vector3f n((p.u - k0.cx) / k0.fx, (p.v - k0.cy) / k0.fy, 1.0f);
    const Eigen::Vector3f X = R * n + t * p.idepth;
    const bool ahead = X.z() > 1e-4f;
    const float z = ahead ? X.z() : 1.0f;
    const float x = X.x() / z, y = X.y() / z, iz = p.idepth / z;
    const float u = k.fx * x + k.cx, v = k.fy * y + k.cy;
    const float hu = (p.u + 0.5f) * scale - 0.5f, hv = (p.v + 0.5f) * scale - 0.5f;
    const bool seen = ahead && inside(cur.value, u, v, 3.0f) && inside(ref.value, hu, hv, 3.0f);
    if (select_view) p.in_view = seen;
    if (!seen) {
      if (!select_view) acc.energy += cutoff;  // left the view during this level
      continue;
    }
    ++acc.visible;
    if (select_view)
      for (std::uint32_t j = 0; j < kPattern; ++j) p.refv[j] = bilinear(ref.value, hu + kPatternX[j], hv + kPatternY[j]);
    alignas(16) float r[kPattern], w[kPattern], gx[kPattern], gy[kPattern], value[kPattern];
    for (std::uint32_t j = 0; j < kPattern; ++j) {
      const Sample c = bilinear_with_gradient(texels, u + kPatternX[j], v + kPatternY[j]);
      value[j] = c.value, gx[j] = c.gx, gy[j] = c.gy;
    }
    const float energy = pattern_residuals(value, gx, gy, p.refv, gain, hb, fb, hub, c2, r, w);
    if (mark_inliers) {
      Point& source = map.kf[p.source >> 16].points[p.source & 0xffffu];
      source.energy = energy;
      source.inlier = energy <= cutoff;
    }
    if (energy > cutoff) {
      acc.energy += cutoff;  // truncated cost: leaving the inlier set is not free
      continue;
    }
    ++acc.inliers;
    acc.energy += energy;
    acc.residuals += kPattern;
    if (!with_jacobians) {
      for (std::uint32_t j = 0; j < kPattern; ++j) acc.squared += r[j] * r[j];
      continue;
    }
    // Geometric Jacobian of the centre pixel, used for the whole pattern (as DSO does): each
    // residual's pose row is gx du + gy dv, so the point adds D S D^T to the pose block with
    // D = [du dv] and S the weighted 2x2 gradient structure of its pattern (one product a point
    // instead of one 8x8 update a pixel). Columns 6, 7: gain and offset. The pattern's sums are
    // taken four pixels at a time.
    const float du[6] = {k.fx * iz, 0, -k.fx * x * iz, -k.fx * x * y, k.fx * (1 + x * x), -k.fx * y};
    const float dv[6] = {0, k.fy * iz, -k.fy * y * iz, -k.fy * (1 + y * y), k.fy * x * y, k.fy * x};
    using A4 = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
    Eigen::Array4f xx = Eigen::Array4f::Zero(), xy = xx, yy = xx, xa = xx, ya = xx, x1 = xx, y1 = xx;
    Eigen::Array4f aa = xx, a1 = xx, ones = xx, rx4 = xx, ry4 = xx, ra4 = xx, r14 = xx;
    for (std::uint32_t h = 0; h < kPattern; h += 4) {
      const Eigen::Array4f wh = A4(w + h), gxh = A4(gx + h), gyh = A4(gy + h), rh = A4(r + h);
      const Eigen::Array4f ja = -gain * (Eigen::Map<const Eigen::Array4f>(p.refv + h) - hb);  // d r / d a; d r / d b = -1
      const Eigen::Array4f wx = wh * gxh, wy = wh * gyh, wa = wh * ja;
      xx += wx * gxh, xy += wx * gyh, yy += wy * gyh;
      xa += wx * ja, ya += wy * ja, x1 += wx, y1 += wy;
      aa += wa * ja, a1 += wa, ones += wh;
      rx4 += wx * rh, ry4 += wy * rh, ra4 += wa * rh, r14 += wh * rh;
    }
    const float sxx = xx.sum(), sxy = xy.sum(), syy = yy.sum(), sxa = xa.sum(), sya = ya.sum();
    const float sxb = -x1.sum(), syb = -y1.sum(), saa = aa.sum(), sab = -a1.sum(), sbb = ones.sum();
    const float rx = rx4.sum(), ry = ry4.sum(), ra = ra4.sum(), rb = -r14.sum();
    add_pose_block_upper(acc.H, du, dv, sxx, sxy, syy);
    for (int q = 0; q < 6; ++q) {
      acc.H(q, 6) += sxa * du[q] + sya * dv[q];
      acc.H(q, 7) += sxb * du[q] + syb * dv[q];
      acc.g[q] += rx * du[q] + ry * dv[q];
    }
    acc.H(6, 6) += saa, acc.H(6, 7) += sab, acc.H(7, 7) += sbb;
    acc.g[6] += ra, acc.g[7] += rb;
  }
  acc.H = acc.H.selfadjointView<Eigen::Upper>();
  return acc;
}

}  // namespace

void build_tracking_reference(TrackingReference& ref, const MapCore& map) {
  ref.count = 0;
  ref.mean_idepth = 0;
  ref.dirty = false;
  if (map.kf_count == 0) return;
  const std::uint32_t ref_slot = map.order[map.kf_count - 1];
  const Keyframe& reference = map.kf[ref_slot];
  const Scaled k = camera_at(map.cfg.camera, 0);
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    const Keyframe& host = map.kf[slot];
    if (!host.used) continue;
    const Se3 M = reference.T_cw * host.T_cw.inverse();
    for (std::uint32_t i = 0; i < host.count && ref.count < ref.points.size(); ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active || !(p.idepth > 0)) continue;
      RefPoint r;
      r.source = slot << 16 | i;
      if (slot == ref_slot) {
        r.u = p.u, r.v = p.v, r.idepth = p.idepth;
      } else {
        const Vec3 X = M * (Vec3((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0) / p.idepth);
        if (X.z() <= 1e-6) continue;
        r.u = static_cast<float>(k.fx * X.x() / X.z() + k.cx);
        r.v = static_cast<float>(k.fy * X.y() / X.z() + k.cy);
        r.idepth = static_cast<float>(1.0 / X.z());
        if (!inside(reference.pyramid.level[0].value, r.u, r.v, 3.0f)) continue;
      }
      ref.points[ref.count++] = r;
    }
  }
  // Enough points for the pose, not more (tracking is most of the VO's time): an even thinning
  // by index keeps the spread over hosts and image regions.
  const std::uint32_t cap = std::max<std::uint32_t>(1000, map.cfg.width * map.cfg.height / kPixelsPerTrackedPoint);
  if (ref.count > cap) {
    std::uint32_t kept = 0;
    for (std::uint32_t i = 0; i < ref.count; ++i)
      if (static_cast<std::uint64_t>(i) * cap / ref.count != static_cast<std::uint64_t>(i + 1) * cap / ref.count)
        ref.points[kept++] = ref.points[i];
    ref.count = kept;
  }
  double idepth_sum = 0;
  for (std::uint32_t i = 0; i < ref.count; ++i) idepth_sum += ref.points[i].idepth;
  ref.mean_idepth = ref.count > 0 ? idepth_sum / ref.count : 0.0;
}

TrackResult track_frame(TrackingReference& ref, MapCore& map, const CurrentFrame& f, const ScaleBridge& bridge,
                        Se3 guess, double a, double b, FreeBrightness free, std::uint32_t last_level,
                        const TrackResult* resume) {
  TrackResult out;
  if (ref.dirty) build_tracking_reference(ref, map);
  Se3 T = guess;
  const bool affine = map.cfg.photometric == Photometric::affine;
  const std::uint32_t iterations[kMaxLevels] = {8, 8, 10, 10, 10, 10};
  const float hub = huber_threshold(map);
  std::uint32_t levels = std::min(f.frame.levels, kMaxLevels);
  if (resume != nullptr && resume->level > last_level && resume->level < levels) {
    T = resume->T_cw, a = resume->a, b = resume->b;
    levels = resume->level;
  }
  // How far a pose step moves the points in pixels: rotation times f, translation times f and
  // the points' mean inverse depth (level 0 pixels).
  const double focal = camera_at(map.cfg.camera, 0).fx;
  const auto step_pixels = [&](const Vec8& delta) {
    return focal * (delta.segment<3>(3).norm() + delta.head<3>().norm() * ref.mean_idepth);
  };
  // A step is negligible when it moves the points by a small part of the level's pixel and, on a
  // frame whose gain is freed (it may start far off, as after a shutter event, and would otherwise
  // stop where its pose settles), changes the gain by little.
  const auto negligible = [&](const Vec8& delta, std::uint32_t l) {
    return step_pixels(delta) < kNegligibleStep * static_cast<double>(1u << l) &&
           (!free.gain || std::fabs(delta[6]) < kNegligibleGainStep);
  };
  for (std::uint32_t l = levels; l-- > last_level;) {
    const int level = static_cast<int>(l);
    float cutoff = tracking_cutoff(hub, l);
    Accumulated acc = accumulate(ref, map, f, l, T, a, b, cutoff, true, false, true);
    for (int grow = 0; grow < 3 && acc.visible > 0 && acc.inliers * 2 < acc.visible; ++grow) {
      cutoff *= 2;
      acc = accumulate(ref, map, f, l, T, a, b, cutoff, true, false);
    }
    double lambda = 1e-3;
    std::uint32_t refused_in_a_row = 0;
    // A weak prior towards the motion model's prediction: at video rates the camera cannot
    // jump, and it keeps directions the points do not constrain (far scenes) from wandering.
    const Vec3 prior = translation_prior_weight(bridge, f.t_s, kMotionPrior) * Vec3(acc.H(0, 0), acc.H(1, 1), acc.H(2, 2));
    const auto prior_energy = [&](const Se3& T_try) {
      const Vec3 off = (T_try * guess.inverse()).t;
      return prior.dot(off.cwiseProduct(off));
    };
    acc.energy += prior_energy(T);
    for (std::uint32_t it = 0; it < iterations[l] && acc.inliers >= 6; ++it) {
      Mat8 H = acc.H;
      Vec8 g = acc.g;
      const Vec3 off = (T * guess.inverse()).t;
      for (int q = 0; q < 3; ++q) H(q, q) += prior[q], g[q] += prior[q] * off[q];
      for (int q = 0; q < 8; ++q) H(q, q) *= 1 + lambda;
      // Parameters the mode does not estimate are held by a stiff prior.
      if (!affine && !free.gain) H(6, 6) += 1e12;
      if (!affine && !free.offset) H(7, 7) += 1e12;
      const Vec8 delta = -H.ldlt().solve(g);
      if (!delta.allFinite()) break;
      const Se3 T_new = Se3::exp(delta.head<6>()) * T;
      const double a_new = a + delta[6], b_new = b + delta[7];
      Accumulated next = accumulate(ref, map, f, l, T_new, a_new, b_new, cutoff, true, false);
      next.energy += prior_energy(T_new);
      if (next.energy <= acc.energy) {
        const bool small_gain = next.energy > (1.0 - kConverged) * acc.energy;
        T = T_new, a = a_new, b = b_new, acc = next;
        lambda = std::max(lambda * 0.5, 1e-6);
        refused_in_a_row = 0;
        if (small_gain || negligible(delta, l)) break;
      } else {
        // A refused step that would have moved the points by a small part of this level's pixel,
        // or at the finest level two refused steps in a row: the pose is at the bottom of what
        // the noise lets it find (more damping only shrinks the step). A coarse level refusing
        // larger steps keeps trying: from a far guess its basin is long and shallow.
        lambda *= 4;
        ++refused_in_a_row;
        if (lambda > 1e4 || negligible(delta, l) ||
            (refused_in_a_row >= kRefusedStepsToStop && level == 0))
          break;
      }
    }
    if (level == 0) {
      const Accumulated final_pass = accumulate(ref, map, f, 0, T, a, b, cutoff, false, true, true);
      out.visible = final_pass.visible;
      out.inliers = final_pass.inliers;
      out.rms = final_pass.residuals ? static_cast<float>(std::sqrt(final_pass.squared / final_pass.residuals)) : 1e9f;
    } else if (l == last_level) {
      out.visible = acc.visible, out.inliers = acc.inliers;
      out.mean_energy = acc.visible ? acc.energy / acc.visible : 1e30;
    }
  }
  out.T_cw = T, out.a = a, out.b = b;
  out.level = last_level;
  const bool finite = T.R.allFinite() && T.t.allFinite() && std::isfinite(a) && std::isfinite(b);
  if (last_level > 0) {
    out.ok = finite;
    return out;
  }
  out.ok = finite && out.inliers >= 20 && out.inliers * 10 >= out.visible * 3 && out.rms < 5.0f * hub;
  return out;
}

}  // namespace bolo::vo
