// Immature points: each new frame with a known pose narrows a point's inverse-depth interval by
// searching its host pattern along the epipolar segment in the frame (discrete steps, then
// Gauss-Newton along the line), keeping the match only when it is unambiguous. A point whose
// interval is tight enough against the scene's typical inverse depth becomes active.

#include <algorithm>
#include <cmath>

#include "state.hpp"

namespace bolo::vo {
namespace {

constexpr float kMaxSearchPixels = 40.0f;
// Tracked points below which a new keyframe also activates the points no baseline could place
// (activate_mature_points). Tracking starves below 40 (odometry.cpp).
constexpr std::uint32_t kRotationActivationInliers = 50;

struct Projection {
  Eigen::Vector3f A, t;  // X(idepth) = A + t * idepth (homogeneous)
};

bool project(const Projection& pr, const Scaled& k, float idepth, float& u, float& v) {
  const Eigen::Vector3f X = pr.A + pr.t * idepth;
  if (X.z() <= 1e-4f) return false;
  u = k.fx * X.x() / X.z() + k.cx, v = k.fy * X.y() / X.z() + k.cy;
  return true;
}

// Inverse depth that projects to pixel (u, v) on the epipolar line, from the better-conditioned
// image coordinate.
float idepth_at(const Projection& pr, const Scaled& k, float u, float v, bool use_x) {
  if (use_x) {
    const float x = (u - k.cx) / k.fx;
    const float den = x * pr.t.z() - pr.t.x();
    return std::fabs(den) < 1e-9f ? -1.0f : (pr.A.x() - x * pr.A.z()) / den;
  }
  const float y = (v - k.cy) / k.fy;
  const float den = y * pr.t.z() - pr.t.y();
  return std::fabs(den) < 1e-9f ? -1.0f : (pr.A.y() - y * pr.A.z()) / den;
}

// The pattern's energy at (u, v): bilinear() and huber_weight() four pattern pixels at a time
// (lane by lane the same arithmetic), the terms summed in pattern order. `stop`: the second half
// is skipped once the sum reaches it (the terms are >= 0 and such a float sum never decreases, so
// the full energy would be >= stop too).
float pattern_energy(const Level& cur, const float* ref, float gain, float offset, float u, float v,
                     float hub, float stop = 3.4e38f) {
  float e = 0;
  const std::size_t w = cur.value.width;
  for (std::uint32_t h = 0; h < kPattern && !(e >= stop); h += 4) {
    const Eigen::Array4f x = u + Eigen::Map<const Eigen::Array4f>(kPatternX + h);
    const Eigen::Array4f y = v + Eigen::Map<const Eigen::Array4f>(kPatternY + h);
    alignas(16) float c00[4], c01[4], c10[4], c11[4], fx[4], fy[4];
    for (int j = 0; j < 4; ++j) {
      const auto xi = static_cast<std::uint32_t>(x[j]), yi = static_cast<std::uint32_t>(y[j]);
      fx[j] = x[j] - static_cast<float>(xi), fy[j] = y[j] - static_cast<float>(yi);
      const float* p = cur.value.data + std::size_t{yi} * w + xi;
      c00[j] = p[0], c01[j] = p[1], c10[j] = p[w], c11[j] = p[w + 1];
    }
    using A = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
    const Eigen::Array4f top = A(c00) + A(fx) * (A(c01) - A(c00));
    const Eigen::Array4f bottom = A(c10) + A(fx) * (A(c11) - A(c10));
    const Eigen::Array4f value = top + A(fy) * (bottom - top);
    const Eigen::Array4f r = value - (gain * Eigen::Map<const Eigen::Array4f>(ref + h) + offset);
    const Eigen::Array4f ra = r.abs();
    const Eigen::Array4f hw = (ra <= hub).select(Eigen::Array4f::Ones(), hub / ra);
    const Eigen::Array4f terms = hw * r * r * (2.0f - hw);
    for (int j = 0; j < 4; ++j) e += terms[j];
  }
  return e;
}

}  // namespace

float typical_idepth(MapCore& s) {
  float* v = s.scratch.data();
  std::size_t n = 0;
  for (const Keyframe& kf : s.kf)
    if (kf.used)
      for (std::uint32_t i = 0; i < kf.count && n < s.scratch.size(); ++i)
        if (kf.points[i].status == PointStatus::active) v[n++] = kf.points[i].idepth;
  return upper_median(v, n);
}

void search_immature_points(MapCore& s, const CurrentFrame& f, const MotionModel& motion, const BrightnessTrack& brightness,
                            float extra_margin_px) {
  const Level& cur = f.frame.level[0];
  const Scaled k = camera_at(s.cfg.camera, 0);
  const float hub = huber_threshold(s);
  const float good_energy = kPattern * hub * hub * 4.0f;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    Keyframe& host = s.kf[slot];
    if (!host.used) continue;
    const Se3 M = motion.T_cw * host.T_cw.inverse();
    if (M.t.norm() < 1e-9) continue;
    const Eigen::Matrix3f R = M.R.cast<float>();
    const Eigen::Vector3f t = M.t.cast<float>();
    const Level& ref = host.pyramid.level[0];
    const float gain = static_cast<float>(std::exp(brightness.a - host.a));
    const float offset = static_cast<float>(brightness.b - std::exp(brightness.a - host.a) * host.b);
    for (std::uint32_t i = 0; i < host.count; ++i) {
      Point& p = host.points[i];
      if (p.status != PointStatus::immature) continue;
      const Projection pr{R * Eigen::Vector3f((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0f), t};
      float u0, v0, u1, v1;
      if (!project(pr, k, p.idepth_min, u0, v0)) continue;
      // The far end: the current bound, or as far as the search is allowed to reach.
      float far_idepth = p.idepth_max;
      if (far_idepth < 0) {
        float ue, ve;
        const float probe = p.idepth_min + 0.05f;
        if (!project(pr, k, probe, ue, ve)) continue;
        const float per_unit = std::hypot(ue - u0, ve - v0) / 0.05f;
        far_idepth = p.idepth_min + (per_unit > 1e-6f ? kMaxSearchPixels / per_unit : 10.0f);
      }
      if (!project(pr, k, far_idepth, u1, v1)) {
        u1 = u0, v1 = v0;
      }
      float du = u1 - u0, dv = v1 - v0;
      float length = std::hypot(du, dv);
      if (length < 1.5f) {
        // No baseline: the depth is not observable here, but whether the point is still seen
        // where a rotation puts it is (activate_mature_points).
        if (length < 0.5f && inside(cur.value, u0, v0, 3.0f) && p.still_matches < 255) {
          float refv[kPattern];
          for (std::uint32_t j = 0; j < kPattern; ++j) refv[j] = bilinear(ref.value, p.u + kPatternX[j], p.v + kPatternY[j]);
          if (pattern_energy(cur, refv, gain, offset, u0, v0, hub, good_energy) < good_energy) ++p.still_matches;
        }
        continue;
      }
      if (length > kMaxSearchPixels) {
        du *= kMaxSearchPixels / length, dv *= kMaxSearchPixels / length;
        length = kMaxSearchPixels;
      }
      const float ex = du / length, ey = dv / length;
      float refv[kPattern];
      // How well the pattern's texture pins a position along the line: gradient energy along
      // the line (a) against across it (b). An edge parallel to the line can slide along it.
      float along = 0, across = 0;
      for (std::uint32_t j = 0; j < kPattern; ++j) {
        const Sample h = bilinear_with_gradient(ref.value, ref.gx, ref.gy, p.u + kPatternX[j], p.v + kPatternY[j]);
        refv[j] = h.value;
        const float ga = h.gx * ex + h.gy * ey, gc = -h.gx * ey + h.gy * ex;
        along += ga * ga, across += gc * gc;
      }
      const float pixel_error = 0.2f + 0.2f * (along + across) / std::max(along, 1e-6f);
      if (pixel_error > 4.0f) continue;  // this line says nothing about the point's depth
      // Discrete search, one pixel per step.
      float best = 1e30f, second = 1e30f, best_s = -1;
      const auto steps = static_cast<std::uint32_t>(length) + 1;
      for (std::uint32_t q = 0; q <= steps; ++q) {
        const float sq = static_cast<float>(q);
        const float uq = u0 + ex * sq, vq = v0 + ey * sq;
        if (!inside(cur.value, uq, vq, 3.0f)) continue;
        // An energy at or above `second` (>= best) changes neither: its sum may stop there.
        const float e = pattern_energy(cur, refv, gain, offset, uq, vq, hub, second);
        if (e < best) {
          if (best_s >= 0 && std::fabs(sq - best_s) > 2.0f) second = best;
          best = e, best_s = sq;
        } else if (e < second && std::fabs(sq - best_s) > 2.0f) {
          second = e;
        }
      }
      if (best_s < 0) continue;
      // Gauss-Newton along the line.
      float sb = best_s;
      for (int it = 0; it < 3; ++it) {
        float H = 0, g = 0;
        for (std::uint32_t j = 0; j < kPattern; ++j) {
          const Sample c = bilinear_with_gradient(f.frame_texels[0], u0 + ex * sb + kPatternX[j], v0 + ey * sb + kPatternY[j]);
          const float r = c.value - (gain * refv[j] + offset);
          const float J = c.gx * ex + c.gy * ey;
          const float w = huber_weight(r, hub);
          H += w * J * J, g += w * J * r;
        }
        if (H < 1e-6f) break;
        const float step = std::max(-0.5f, std::min(0.5f, -g / H));
        const float sn = sb + step;
        if (!inside(cur.value, u0 + ex * sn, v0 + ey * sn, 3.0f)) break;
        sb = sn;
      }
      const float e_final = pattern_energy(cur, refv, gain, offset, u0 + ex * sb, v0 + ey * sb, hub);
      if (e_final > good_energy) {
        if (++p.bad > 4) p.status = PointStatus::empty;
        continue;
      }
      p.quality = second / std::max(e_final, 1e-3f);
      if (p.quality < 2.0f && length > 3.0f) continue;  // repetitive texture: ambiguous
      // Interval: the match +- (half a pixel + a share of the search length when ambiguous).
      const float margin = std::max(0.5f, pixel_error) + (p.quality < 2.0f ? 1.0f : 0.0f) + extra_margin_px;
      const bool use_x = std::fabs(ex) >= std::fabs(ey);
      float ia = idepth_at(pr, k, u0 + ex * (sb - margin), v0 + ey * (sb - margin), use_x);
      float ib = idepth_at(pr, k, u0 + ex * (sb + margin), v0 + ey * (sb + margin), use_x);
      float im = idepth_at(pr, k, u0 + ex * sb, v0 + ey * sb, use_x);
      if (ia > ib) std::swap(ia, ib);
      if (!(im > 0) || !(ib > 0)) continue;
      ia = std::max(ia, 0.0f);
      // Intersect with what earlier frames allowed; a match outside it contradicts them.
      if (p.idepth_max >= 0 && p.good > 0 && (ib < p.idepth_min || ia > p.idepth_max)) {
        p.good = 0;
        if (++p.bad > 4) p.status = PointStatus::empty;
        p.idepth_min = ia, p.idepth_max = ib, p.idepth = im;
        continue;
      }
      ++p.good;
      p.idepth_min = p.idepth_max >= 0 ? std::max(ia, p.idepth_min) : ia;
      p.idepth_max = p.idepth_max >= 0 ? std::min(ib, p.idepth_max) : ib;
      if (p.idepth_min > p.idepth_max) std::swap(p.idepth_min, p.idepth_max);
      p.idepth = im;
    }
  }
}

void activate_mature_points(MapCore& s, TrackingReference& ref, ScaleBridge& bridge, const InitialiserState& init, double t_s,
                            std::uint32_t tracked_points) {
  ref.dirty = true;
  // A point is ready when its interval is narrow against the scene's typical inverse depth, not
  // against its own estimate: relative to its own, the points whose inverse depth came out too
  // large (too near) pass first, and a map built from them shrinks the next motion estimates,
  // whose matches then come out nearer still (handheld street: the median inverse depth went
  // from 1 to 70 in a second).
  const float typical = typical_idepth(s);
  // A map about to run out while no new point can be placed: the camera turns about its
  // centre (a pan, a turn on the spot), so every new point's epipolar segment is a fraction of a
  // pixel or as long as the translation's noise makes it, and nothing matures. Under a rotation
  // the residuals do not depend on depth, so such points are activated at the typical inverse
  // depth (or the nearest to it their interval allows) and track the rotation; the window BA
  // refines the depths once the camera translates. Without this a 30 deg/s pan lost the track
  // every ~1.5 s, when the view had turned away from the initial map.
  const bool rotation_only = tracked_points < kRotationActivationInliers;
  bool placed_without_baseline = false;
  for (std::uint32_t slot = 0; slot < kMaxKeyframes; ++slot) {
    Keyframe& host = s.kf[slot];
    if (!host.used) continue;
    for (std::uint32_t i = 0; i < host.count; ++i) {
      Point& p = host.points[i];
      if (p.status != PointStatus::immature) continue;
      if (rotation_only && ((p.good >= 2 && p.quality >= 2.0f) || (p.good == 0 && p.still_matches >= 2))) {
        p.status = PointStatus::active;
        p.energy = 0;
        if (p.good == 0) {
          p.idepth = typical > 0 ? typical : 1.0f;
          placed_without_baseline = true;
        } else if (typical > 0 && p.idepth_max >= 0) p.idepth = std::max(p.idepth_min, std::min(p.idepth_max, typical));
        continue;
      }
      if (p.good < 2 || p.idepth_max < 0) continue;
      const float width = p.idepth_max - p.idepth_min;
      if (p.idepth > 1e-3f && width < 0.2f * (typical > 0 ? typical : p.idepth) && p.quality >= 2.5f) {
        p.status = PointStatus::active;
        p.energy = 0;
      }
    }
  }
  // The new view's points have no depth of their own: the map's scale breaks here.
  if (placed_without_baseline) note_map_break(bridge, s.cfg, init.map_without_baseline, t_s);
}

}  // namespace bolo::vo
