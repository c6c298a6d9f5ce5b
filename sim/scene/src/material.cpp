#include <algorithm>
#include <cmath>

#include "bolo/sim/scene/material.hpp"
#include "random.hpp"

namespace bolo::sim::scene {
namespace {

using detail::hash;
using detail::ifloor;
using detail::signed_unit;
using detail::u64;
using detail::unit;

inline double wrap(double x, double period) { return x - std::floor(x / period) * period; }

struct Eval {
  const SurfacePoint& s;
  double b;  // base incl. the per-object offset
  std::uint64_t seed;

  double operator()(const Plain&) const { return b; }

  double operator()(const Checker& c) const {
    const std::int64_t i = ifloor(s.uv.x() / c.square_m), j = ifloor(s.uv.y() / c.square_m);
    return ((i + j) & 1) == 0 ? c.cold_k : c.hot_k;
  }

  double operator()(const Tiles& t) const {
    const double u = s.uv.x(), v = s.uv.y();
    const std::int64_t i = ifloor(u / t.size_m), j = ifloor(v / t.size_m);
    const double lu = u - static_cast<double>(i) * t.size_m, lv = v - static_cast<double>(j) * t.size_m;
    if (lu < t.joint_m || lv < t.joint_m) return b + t.joint_dk;
    return b + t.tile_jitter_k * signed_unit(hash(seed ^ s.object_seed, u64(i), u64(j), 0x711E));
  }

  double operator()(const RoadMarkings& r) const {
    const double u = s.uv.x(), v = s.uv.y();
    double t = b;
    // Repair patches: one chance per 10 m x 4 m cell, a rectangle inside it.
    {
      const std::int64_t ci = ifloor(u / 10.0), cj = ifloor(v / 4.0);
      const std::uint64_t h = hash(seed, u64(ci), u64(cj), 0xFA7C);
      if (unit(h) < 0.3) {
        const double u0 = static_cast<double>(ci) * 10.0 + 1.0 + 5.0 * unit(detail::mix64(h + 1));
        const double v0 = static_cast<double>(cj) * 4.0 + 0.3 + 1.5 * unit(detail::mix64(h + 2));
        const double lu = 1.0 + 3.0 * unit(detail::mix64(h + 3)), lv = 0.6 + 1.5 * unit(detail::mix64(h + 4));
        if (u >= u0 && u <= u0 + lu && v >= v0 && v <= v0 + lv)
          t += r.patch_dk * signed_unit(detail::mix64(h + 5));
      }
    }
    // Warm tyre tracks.
    if (r.track_dk != 0.0) {
      const double av = std::abs(v);
      for (double c : {r.lane_centre_m - 0.8, r.lane_centre_m + 0.8}) {
        const double d = (av - c) / 0.45;  // smooth bump, 0.45 m half width
        if (d * d < 1.0) t += r.track_dk * (1.0 - d * d) * (1.0 - d * d);
      }
    }
    bool paint = false;
    bool in_gap = false;
    for (const auto& g : r.gaps) in_gap = in_gap || (u >= g.first && u <= g.second);
    if (!in_gap) {
      const double hw = 0.5 * r.line_width_m;
      if (std::abs(v) < hw && wrap(u, r.centre_dash_m + r.centre_gap_m) < r.centre_dash_m) paint = true;
      if (std::abs(std::abs(v) - r.edge_offset_m) < hw) paint = true;
    }
    for (double c : r.crosswalks) {
      if (std::abs(u - c) < 2.0 && std::abs(v) < r.crosswalk_half_width_m) {
        if ((ifloor((v + r.crosswalk_half_width_m) / 0.5) & 1) == 0) paint = true;
      }
    }
    if (paint) t += r.paint_dk;
    return t;
  }

  double operator()(const Facade& f) const {
    const std::uint64_t bh = hash(seed, s.object_seed, 0xFACADE);
    if (s.face == 4) return f.roof_k + 0.8 * signed_unit(detail::mix64(bh + 9));
    if (s.face == 5) return b;
    const double fh = f.floor_height_min_m + (f.floor_height_max_m - f.floor_height_min_m) * unit(detail::mix64(bh + 1));
    const double spacing = f.window_spacing_min_m +
                           (f.window_spacing_max_m - f.window_spacing_min_m) * unit(detail::mix64(bh + 2));
    const double u = s.uv.x(), v = s.uv.y();
    const double width = s.face_size.x(), height = s.face_size.y();
    double t = b;
    const std::int64_t floor_i = ifloor(v / fh);
    const double vf = v - static_cast<double>(floor_i) * fh;
    const std::int64_t floors = ifloor((height - 0.5) / fh);  // full storeys under the parapet
    if (floor_i >= 1 && floor_i <= floors && (vf < 0.2 || vf > fh - 0.05)) t += f.slab_dk;
    if (floor_i < 0 || floor_i >= floors) return t;
    const std::int64_t n = std::max<std::int64_t>(1, ifloor(width / spacing));
    const double margin = 0.5 * (width - static_cast<double>(n) * spacing);
    const double lu = u - margin;
    const std::int64_t col = ifloor(lu / spacing);
    if (col < 0 || col >= n) return t;
    const double xin = lu - static_cast<double>(col) * spacing;  // 0..spacing within the bay
    const std::uint64_t wh = hash(seed ^ s.object_seed, u64(s.face), u64(col), u64(floor_i));
    const double fw = 0.07;  // frame width
    double x0, x1, y0, y1, glass;
    if (floor_i == 0 && unit(detail::mix64(bh + 3 + static_cast<std::uint64_t>(s.face))) < f.shop_probability) {
      x0 = 0.2;
      x1 = spacing - 0.2;
      y0 = 0.4;
      y1 = std::min(fh - 0.4, 2.8);
      glass = f.shop_min_k + (f.shop_max_k - f.shop_min_k) * unit(wh);
    } else {
      x0 = 0.5 * (spacing - f.window_width_m);
      x1 = x0 + f.window_width_m;
      y0 = f.sill_m;
      y1 = f.sill_m + f.window_height_m;
      if (unit(detail::mix64(wh + 1)) < f.lit_fraction)
        glass = f.lit_min_k + (f.lit_max_k - f.lit_min_k) * unit(wh);
      else
        glass = f.dark_min_k + (f.dark_max_k - f.dark_min_k) * unit(wh);
    }
    if (xin >= x0 && xin <= x1 && vf >= y0 && vf <= y1) {
      // Warm air collects at the top of a heated window.
      return glass + 0.8 * ((vf - y0) / (y1 - y0) - 0.5);
    }
    if (xin >= x0 - fw && xin <= x1 + fw && vf >= y0 - fw && vf <= y1 + fw) return t + f.frame_dk;
    return t;
  }

  double operator()(const CarPaint& c) const {
    const double h = std::clamp(c.heat, 0.0, 1.0);
    const double paint = b;
    const Eigen::Vector3d& p = s.p;
    const double l2 = 0.5 * c.length_m, w2 = 0.5 * c.width_m;
    const bool cabin = p.z() > c.body_top_m + 1e-4;
    if (cabin) {
      if (s.face == 4) return paint - 1.5 + 2.0 * h;  // roof, cooled by the sky
      const double m = 0.09;  // pillars / frame
      const bool glass = s.uv.x() > m && s.uv.x() < s.face_size.x() - m && s.uv.y() > 0.04 &&
                         s.uv.y() < s.face_size.y() - m;
      if (glass) return c.glass_k + 1.5 * h + 0.8 * (s.uv.y() / s.face_size.y());
      return paint + 3.0 * h;
    }
    const double bb = c.body_bottom_m, bt = c.body_top_m;
    switch (s.face) {
      case 0: {  // front: radiator grille, headlights
        if (std::abs(p.y()) < 0.55 && p.z() > bb + 0.12 && p.z() < bb + 0.48) {
          const double g = p.y() / 0.3;
          return paint + h * (c.engine_k - paint) * (0.75 + 0.25 * std::exp(-g * g));
        }
        if (std::abs(p.y()) > w2 - 0.35 && std::abs(p.y()) < w2 - 0.08 && p.z() > bt - 0.3 && p.z() < bt - 0.12)
          return paint + 15.0 * h;
        return paint + 18.0 * h * (1.0 - 0.5 * (p.z() - bb) / (bt - bb));
      }
      case 1: {  // rear: exhaust pipe and its warm plume
        const double dy = p.y() - (-w2 + 0.4), dz = p.z() - (bb + 0.08);
        const double r2 = dy * dy + dz * dz;
        const double around = paint + 3.0 * h + 8.0 * h * std::exp(-r2 / (0.25 * 0.25));
        return around + h * (c.exhaust_k - around) * std::exp(-r2 / (0.06 * 0.06));
      }
      case 4: {  // body top: hood (engine underneath), trunk
        if (p.x() > c.cabin_front_m) {
          const double f = (p.x() - c.cabin_front_m) / std::max(1e-6, l2 - c.cabin_front_m);
          return paint + h * (c.hood_k - paint) * (0.55 + 0.45 * f);
        }
        return paint + 2.0 * h;
      }
      case 2:
      case 3: {  // sides: tyres, hot brake discs, warm front fender
        for (double wx : {0.5 * c.wheelbase_m, -0.5 * c.wheelbase_m}) {
          const double dx = p.x() - wx, dz = p.z() - c.wheel_radius_m;
          const double d = std::sqrt(dx * dx + dz * dz);
          if (d < c.wheel_radius_m) {
            if (d < 0.14) return paint + 40.0 * h;  // brake disc / hub
            return paint + 2.0 + h * (c.tyre_k - paint - 2.0);
          }
        }
        const double e = (p.x() - 0.55 * l2) / 0.8;
        return paint + 6.0 * h * std::exp(-e * e);
      }
      default:
        return paint + 30.0 * h;  // underside
    }
  }

  double operator()(const Lamp& l) const {
    if (s.face == 5) {
      const Eigen::Vector2d d = s.uv - 0.5 * s.face_size;
      return l.housing_k + (l.peak_k - l.housing_k) * std::exp(-d.squaredNorm() / (l.radius_m * l.radius_m));
    }
    return l.housing_k;
  }
};

}  // namespace

double Material::temperature_from_base(const SurfacePoint& s, double base) const {
  double b = base;
  if (object_jitter_k != 0.0) b += object_jitter_k * signed_unit(hash(seed, s.object_seed, 0x0B7));
  double t = std::visit(Eval{s, b, seed}, pattern);
  if (noise_k != 0.0 || detail_k != 0.0) {
    const std::uint64_t ns = hash(seed, s.object_seed, static_cast<std::uint64_t>(s.face + 1));
    if (noise_k != 0.0)
      t += noise_k * detail::value_noise(ns, s.uv.x() / noise_scale_m, s.uv.y() / noise_scale_m);
    if (detail_k != 0.0)
      t += detail_k * detail::value_noise(ns + 0xDE7, s.uv.x() / detail_scale_m, s.uv.y() / detail_scale_m);
  }
  return t;
}

}  // namespace bolo::sim::scene
