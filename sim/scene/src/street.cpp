// The `street` scene: a night street in LWIR. See scene.hpp (street_layout) for the geometry:
// main street along x (|y| <= 6 carriageway, sidewalks to |y| = 9, buildings beyond), closed by
// buildings at both ends; a cross street along -y from x = 300 (T junction), closed at its end.
#include <cmath>
#include <memory>
#include <numbers>

#include "bolo/sim/scene/scene.hpp"
#include "path.hpp"
#include "random.hpp"

namespace bolo::sim::scene {
namespace {

namespace L = street_layout;
using detail::PlanarPath;
using detail::Rng;


Box aabox(double x0, double x1, double y0, double y1, double z0, double z1, std::size_t mat, std::uint64_t seed) {
  Box b;
  b.lo = Eigen::Vector3d(std::min(x0, x1), std::min(y0, y1), z0);
  b.hi = Eigen::Vector3d(std::max(x0, x1), std::max(y0, y1), z1);
  b.material = mat;
  b.seed = seed;
  return b;
}

Eigen::Isometry3d planar(double x, double y, double heading) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m.translation() = Eigen::Vector3d(x, y, 0.0);
  return m;
}

// A row of buildings along one side of a street. axis 0: the facade line is y = line and the
// buildings extend to sign * depth in y; axis 1: the line is x = line.
void add_buildings(Scene& s, Rng& rng, std::size_t mat, int axis, double line, double sign, double u0, double u1) {
  double u = u0;
  while (u1 - u > 4.0) {
    double w = rng.uniform(10.0, 26.0);
    if (u1 - (u + w) < 8.0) w = u1 - u;
    const int floors = rng.integer(2, 7);
    const double height = floors * 3.2 + rng.uniform(0.5, 1.2);
    const double depth = rng.uniform(10.0, 16.0);
    const double a = line, b = line + sign * depth;
    if (axis == 0)
      s.add_box(aabox(u, u + w, a, b, 0.0, height, mat, rng.next()));
    else
      s.add_box(aabox(a, b, u, u + w, 0.0, height, mat, rng.next()));
    u += w;
    if (rng.chance(0.25)) u += rng.uniform(1.5, 4.0);  // an alley
  }
}

// A lamp post at (x, y) with its arm reaching `dir` (unit, along x or y) over the road.
void add_lamp_post(Scene& s, Rng& rng, std::size_t pole_mat, double x, double y, const Eigen::Vector2d& dir) {
  const double h = 7.0;
  s.add_box(aabox(x - 0.08, x + 0.08, y - 0.08, y + 0.08, 0.0, h, pole_mat, rng.next()));
  const Eigen::Vector2d end = Eigen::Vector2d(x, y) + 1.7 * dir;
  const Eigen::Vector2d side(-dir.y(), dir.x());
  const Eigen::Vector2d a0 = Eigen::Vector2d(x, y) + 0.04 * side, a1 = end - 0.04 * side;
  s.add_box(aabox(a0.x(), a1.x(), a0.y(), a1.y(), h - 0.08, h, pole_mat, rng.next()));
  Material lamp;
  lamp.name = "lamp";
  lamp.seed = rng.next();
  lamp.pattern = Lamp{rng.uniform(320.0, 350.0), rng.uniform(297.0, 303.0), 0.15};
  const std::size_t lm = s.add_material(lamp);
  const Eigen::Vector2d c = Eigen::Vector2d(x, y) + 1.5 * dir;
  const Eigen::Vector2d half = 0.3 * side.cwiseAbs() + 0.17 * dir.cwiseAbs();
  s.add_box(aabox(c.x() - half.x(), c.x() + half.x(), c.y() - half.y(), c.y() + half.y(), h - 0.22, h - 0.08, lm,
                  rng.next()));
}

struct CarShape {
  double length, width, body_top, cabin_top, cabin_rear, cabin_front;
};

CarShape random_shape(Rng& rng) {
  if (rng.chance(0.15)) {  // van
    const double len = rng.uniform(4.8, 5.3);
    return {len, 1.95, 1.2, 2.0, -0.5 * len + 0.25, 0.5 * len - 0.9};
  }
  const double len = rng.uniform(4.0, 4.8);
  return {len, rng.uniform(1.72, 1.86), rng.uniform(0.88, 1.0), rng.uniform(1.40, 1.52),
          -0.5 * len + rng.uniform(0.8, 1.1), 0.5 * len - rng.uniform(1.25, 1.5)};
}

// A car with its own material; `motion` -1 for a parked car placed by `placement`.
void add_car(Scene& s, Rng& rng, const Eigen::Isometry3d& placement, int motion, double heat) {
  const CarShape sh = random_shape(rng);
  Material m;
  m.name = motion < 0 ? "parked car" : "moving car";
  m.seed = rng.next();
  m.base_k = rng.uniform(274.5, 279.5);  // paint mirrors the sky: a little below the air
  m.noise_k = 0.4;
  m.noise_scale_m = 1.0;
  CarPaint c;
  c.length_m = sh.length;
  c.width_m = sh.width;
  c.body_bottom_m = 0.12;
  c.body_top_m = sh.body_top;
  c.cabin_top_m = sh.cabin_top;
  c.cabin_rear_m = sh.cabin_rear;
  c.cabin_front_m = sh.cabin_front;
  c.wheelbase_m = 0.6 * sh.length;
  c.heat = heat;
  c.engine_k = rng.uniform(340.0, 368.0);
  c.exhaust_k = rng.uniform(345.0, 370.0);
  c.hood_k = rng.uniform(312.0, 326.0);
  c.tyre_k = rng.uniform(303.0, 312.0);
  c.glass_k = rng.uniform(266.0, 272.0);
  m.pattern = c;
  const std::size_t mat = s.add_material(m);
  const std::uint64_t seed = rng.next();
  Box body;
  body.lo = Eigen::Vector3d(-0.5 * sh.length, -0.5 * sh.width, 0.12);
  body.hi = Eigen::Vector3d(0.5 * sh.length, 0.5 * sh.width, sh.body_top);
  body.material = mat;
  body.seed = seed;
  Box cabin;
  cabin.lo = Eigen::Vector3d(sh.cabin_rear, -0.5 * sh.width + 0.08, sh.body_top);
  cabin.hi = Eigen::Vector3d(sh.cabin_front, 0.5 * sh.width - 0.08, sh.cabin_top);
  cabin.material = mat;
  cabin.seed = seed;
  if (motion >= 0) {
    body.motion = cabin.motion = motion;
  } else {
    body.placement = cabin.placement = placement;
  }
  s.add_box(body);
  s.add_box(cabin);
}

double parked_heat(Rng& rng) {
  if (rng.chance(0.3)) return rng.uniform(0.25, 0.6);  // parked a few minutes ago
  return rng.uniform(0.0, 0.05);
}

// Parked cars along a strip: centre line at lateral `lat`, from u0 to u1 along the street.
// axis 0: the street runs along x; axis 1: along y. heading: the cars' heading (radians).
void park_strip(Scene& s, Rng& rng, int axis, double lat, double heading, double u0, double u1, double ex0,
                double ex1) {
  double u = u0 + rng.uniform(0.0, 3.0);
  while (u < u1 - 6.0) {
    const double slot = rng.uniform(5.8, 7.6);
    const bool excluded = u + slot > ex0 && u < ex1;
    if (!excluded && rng.chance(0.6)) {
      const double c = u + 0.5 * slot + rng.uniform(-0.4, 0.4);
      const double l = lat + rng.uniform(-0.12, 0.12);
      const double h = heading + rng.uniform(-0.03, 0.03);
      const Eigen::Isometry3d p = axis == 0 ? planar(c, l, h) : planar(l, c, h);
      add_car(s, rng, p, -1, parked_heat(rng));
    }
    u += slot;
  }
}

// Cars circulating along a path, wrapping from its end to its start (both inside buildings).
void add_traffic(Scene& s, Rng& rng, const std::shared_ptr<const PlanarPath>& path, double speed, int cars) {
  const double len = path->length();
  for (int k = 0; k < cars; ++k) {
    const double s0 = (k + rng.uniform(-0.15, 0.15)) * len / cars;
    const int motion = s.add_motion([path, speed, s0, len](double t) {
      double arc = std::fmod(s0 + speed * t, len);
      if (arc < 0.0) arc += len;
      const auto st = path->at(arc);
      return planar(st.p.x(), st.p.y(), st.heading);
    });
    add_car(s, rng, Eigen::Isometry3d::Identity(), motion, rng.uniform(0.85, 1.0));
  }
}

}  // namespace

Scene make_street_scene(std::uint64_t seed) {
  Rng rng(seed ^ 0x57EE7ull);
  Scene s;
  s.name = "street";
  s.sky = Sky{232.0, 258.0, 0.2};
  s.atmosphere = Atmosphere{278.0, 1500.0};
  s.viewpoint = Eigen::Vector3d(150.0, -7.2, 1.65);
  s.viewpoint_yaw = std::numbers::pi / 3.0;

  const double hw = L::kRoadHalfWidth, sw = L::kSidewalkOuter, cx = L::kCrossX;
  const double west = L::kMainWest, east = L::kMainEast, south = L::kCrossSouth;

  Material ground;
  ground.name = "ground";
  ground.base_k = 274.0;
  ground.noise_k = 1.5;
  ground.noise_scale_m = 3.0;
  ground.detail_k = 0.5;
  ground.detail_scale_m = 0.35;
  ground.seed = rng.next();
  const std::size_t ground_m = s.add_material(ground);

  Material road;
  road.name = "asphalt";
  road.base_k = 277.5;
  road.noise_k = 1.0;
  road.noise_scale_m = 4.0;
  road.detail_k = 0.4;
  road.detail_scale_m = 0.25;
  road.seed = rng.next();
  RoadMarkings main_marks;
  main_marks.gaps = {{cx - sw, cx + sw}};
  main_marks.crosswalks = {cx - sw - 2.5, cx + sw + 2.5};
  road.pattern = main_marks;
  const std::size_t road_main_m = s.add_material(road);
  RoadMarkings cross_marks;
  cross_marks.crosswalks = {sw + 2.5};
  road.pattern = cross_marks;
  road.seed = rng.next();
  const std::size_t road_cross_m = s.add_material(road);

  Material sidewalk;
  sidewalk.name = "sidewalk";
  sidewalk.base_k = 279.0;
  sidewalk.noise_k = 0.6;
  sidewalk.noise_scale_m = 5.0;
  sidewalk.detail_k = 0.25;
  sidewalk.detail_scale_m = 0.2;
  sidewalk.pattern = Tiles{};
  sidewalk.seed = rng.next();
  const std::size_t sidewalk_m = s.add_material(sidewalk);

  Material facade;
  facade.name = "facade";
  facade.base_k = 283.0;
  facade.object_jitter_k = 2.0;
  facade.noise_k = 0.8;
  facade.noise_scale_m = 4.0;
  facade.detail_k = 0.3;
  facade.detail_scale_m = 0.3;
  facade.pattern = Facade{};
  facade.seed = rng.next();
  const std::size_t facade_m = s.add_material(facade);

  Material pole;
  pole.name = "pole";
  pole.base_k = 273.5;
  pole.object_jitter_k = 1.0;
  pole.noise_k = 0.3;
  pole.noise_scale_m = 1.0;
  pole.seed = rng.next();
  const std::size_t pole_m = s.add_material(pole);

  // Ground, roads (1 cm above the ground), sidewalks.
  Quad g;
  g.material = ground_m;
  g.seed = rng.next();
  s.add_quad(g);
  Quad main_road;
  main_road.origin = Eigen::Vector3d(0.0, 0.0, 0.01);
  main_road.u_min = west;
  main_road.u_max = east;
  main_road.v_min = -hw;
  main_road.v_max = hw;
  main_road.material = road_main_m;
  main_road.seed = rng.next();
  s.add_quad(main_road);
  Quad cross_road;  // u along -y (from the main street's centre line), v = x - cx
  cross_road.origin = Eigen::Vector3d(cx, 0.0, 0.01);
  cross_road.u_axis = -Eigen::Vector3d::UnitY();
  cross_road.v_axis = Eigen::Vector3d::UnitX();
  cross_road.u_min = hw;
  cross_road.u_max = -south;
  cross_road.v_min = -hw;
  cross_road.v_max = hw;
  cross_road.material = road_cross_m;
  cross_road.seed = rng.next();
  s.add_quad(cross_road);
  const double zs = L::kSidewalkHeight;
  s.add_box(aabox(west, east, hw, sw, 0.0, zs, sidewalk_m, rng.next()));
  s.add_box(aabox(west, cx - hw, -sw, -hw, 0.0, zs, sidewalk_m, rng.next()));
  s.add_box(aabox(cx + hw, east, -sw, -hw, 0.0, zs, sidewalk_m, rng.next()));
  s.add_box(aabox(cx - sw, cx - hw, south, -sw, 0.0, zs, sidewalk_m, rng.next()));
  s.add_box(aabox(cx + hw, cx + sw, south, -sw, 0.0, zs, sidewalk_m, rng.next()));

  // Buildings: both sides of the main street, both sides of the cross street, and the three
  // buildings closing the streets (moving cars appear from and vanish into these).
  add_buildings(s, rng, facade_m, 0, sw, +1.0, west, east);
  add_buildings(s, rng, facade_m, 0, -sw, -1.0, west, cx - sw);
  add_buildings(s, rng, facade_m, 0, -sw, -1.0, cx + sw, east);
  add_buildings(s, rng, facade_m, 1, cx - sw, -1.0, south, -sw - 17.0);
  add_buildings(s, rng, facade_m, 1, cx + sw, +1.0, south, -sw - 17.0);
  s.add_box(aabox(west - 15.0, west, -25.0, 25.0, 0.0, 15.5, facade_m, rng.next()));
  s.add_box(aabox(east, east + 15.0, -25.0, 25.0, 0.0, 18.5, facade_m, rng.next()));
  s.add_box(aabox(cx - 20.0, cx + 20.0, south - 15.0, south, 0.0, 12.5, facade_m, rng.next()));

  // Lamp posts, alternating sides every 12.5 m, 0.4 m behind the kerb.
  const double pole_lat = hw + 0.4;
  int k = 0;
  for (double x = west + 10.0; x < east - 5.0; x += 12.5, ++k) {
    const bool north = (k % 2) == 0;
    if (!north && x > cx - sw - 3.0 && x < cx + sw + 3.0) continue;
    add_lamp_post(s, rng, pole_m, x, north ? pole_lat : -pole_lat, Eigen::Vector2d(0.0, north ? -1.0 : 1.0));
  }
  k = 0;
  for (double y = -sw - 12.0; y > south + 5.0; y -= 12.5, ++k) {
    const bool west_side = (k % 2) == 0;
    add_lamp_post(s, rng, pole_m, west_side ? cx - pole_lat : cx + pole_lat, y,
                  Eigen::Vector2d(west_side ? 1.0 : -1.0, 0.0));
  }

  // Parked cars (right-hand traffic: facing the direction of the adjacent lane).
  const double park = 0.5 * (L::kRoadHalfWidth + 4.0);  // 5 m: middle of the parking strip
  park_strip(s, rng, 0, park, std::numbers::pi, west, east, cx - sw - 12.0, cx + sw + 12.0);
  park_strip(s, rng, 0, -park, 0.0, west, east, cx - sw - 12.0, cx + sw + 12.0);
  park_strip(s, rng, 1, cx - park, -std::numbers::pi / 2.0, south, -sw, -sw - 8.0, 0.0);
  park_strip(s, rng, 1, cx + park, std::numbers::pi / 2.0, south, -sw, -sw - 8.0, 0.0);

  // Traffic. Westbound in the main street's north lane, from inside the east building to inside
  // the west one. Northbound in the cross street, turning right into the main street's
  // eastbound lane, into the east building. (The `drive` trajectory uses the main street's
  // eastbound lane west of the junction and the cross street's southbound lane: no collision.)
  const double lane = L::kLaneOffset;
  auto westbound = std::make_shared<const PlanarPath>(Eigen::Vector2d(east + 15.0, lane), std::numbers::pi,
                                                      std::vector<PlanarPath::Segment>{{east - west + 30.0, 0.0}});
  add_traffic(s, rng, westbound, rng.uniform(9.5, 12.5), 6);
  const double turn_len = 14.0;
  const Eigen::Vector2d a = detail::turn_displacement(turn_len, -std::numbers::pi / 2.0);  // forward a.x, right -a.y
  const double y_turn = -lane - a.x();
  const double x_after = cx + lane - a.y();
  auto northbound = std::make_shared<const PlanarPath>(
      Eigen::Vector2d(cx + lane, south - 10.0), std::numbers::pi / 2.0,
      std::vector<PlanarPath::Segment>{{y_turn - (south - 10.0), 0.0}, {turn_len, -std::numbers::pi / 2.0},
                                       {east + 15.0 - x_after, 0.0}});
  add_traffic(s, rng, northbound, rng.uniform(9.0, 12.0), 6);
  return s;
}

}  // namespace bolo::sim::scene
