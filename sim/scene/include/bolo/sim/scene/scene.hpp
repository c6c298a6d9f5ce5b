#pragma once
// A 3D thermal world: textured quads (ground, roads, walls) and boxes (buildings, cars, poles,
// lamps), some of which move, under a sky, seen through an atmosphere. Render it with
// bolo::sim::scene::Renderer. World frame: z up, ground z = 0 (see pose.hpp).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "bolo/sim/scene/blackbody.hpp"
#include "bolo/sim/scene/material.hpp"

namespace bolo::sim::scene {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A planar rectangle (or an infinite plane): origin + u * u_axis + v * v_axis for u in
// [u_min, u_max], v in [v_min, v_max]. The axes must be orthonormal. Two-sided.
struct Quad {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v_axis = Eigen::Vector3d::UnitY();
  double u_min = -kInfinity, u_max = kInfinity;
  double v_min = -kInfinity, v_max = kInfinity;
  std::size_t material = 0;
  std::uint64_t seed = 0;  // object_seed of its surface points
};

// A box [lo, hi] in its own frame, placed by `placement` (box frame -> parent frame). The parent
// is the world for a static box, and the frame of motions[motion] at time t for a moving one
// (world_from_box(t) = motions[motion](t) * placement). Surface points are given in the box
// frame, so a car made of several boxes with identity placements shares one frame.
struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Ones();
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  std::size_t material = 0;
  int motion = -1;  // -1: static
  std::uint64_t seed = 0;
};

// world_from_object at time t: rigid motion of a group of boxes.
using Motion = std::function<Eigen::Isometry3d(double t)>;

// What a ray that hits nothing sees, by elevation e above the horizon (world z):
// T = zenith + (horizon - zenith) * exp(-sin(e) / falloff); rays below the horizon see horizon_k.
struct Sky {
  double zenith_k = 232.0;
  double horizon_k = 258.0;
  double falloff = 0.2;
  double temperature(const Eigen::Vector3d& world_direction) const;
};

// Path through air: T = T_surface * tau + air_k * (1 - tau), tau = exp(-distance / extinction).
// (Linear in kelvin: a small-contrast approximation of the radiance mix.) Infinite = clear.
struct Atmosphere {
  double air_k = 278.0;
  double extinction_length_m = kInfinity;
};

struct Scene {
  std::string name = "custom";
  std::vector<Material> materials;
  std::vector<Motion> motions;
  std::vector<Quad> quads;
  std::vector<Box> boxes;
  Sky sky;
  Atmosphere atmosphere;
  // A pose from which the scene is meant to be seen (camera-to-world), e.g. for tests/demos.
  Eigen::Vector3d viewpoint = Eigen::Vector3d(0.0, 0.0, 1.5);
  double viewpoint_yaw = 0.0;  // radians, 0 = looking along +x

  std::size_t add_material(Material m);
  int add_motion(Motion m);
  std::size_t add_quad(const Quad& q);
  std::size_t add_box(const Box& b);
  // world_from_box at time t.
  Eigen::Isometry3d box_to_world(const Box& b, double t) const;
  // Throws std::invalid_argument naming the object on a bad material/motion index, an inverted
  // box or non-orthonormal quad axes.
  void validate() const;
};

std::vector<std::string> scene_names();  // {"street", "lab", "checker"}

// A named scene, deterministic from the seed:
//   street   night street in LWIR (asphalt with markings, facades with warm windows, parked and
//            moving cars with hot engines, poles with hot lamps, cold sky, a T junction)
//   lab      a room at ~295 K with a large blackbody target filling the view from the
//            `blackbody` trajectory's pose; the target follows BlackbodySchedule{}
//   checker  a high-contrast checkerboard ground (1 m squares) and wall (0.25 m squares)
// Throws std::invalid_argument naming the unknown scene and listing the valid ones.
Scene make_scene(const std::string& name, std::uint64_t seed);

Scene make_street_scene(std::uint64_t seed);
Scene make_lab_scene(const BlackbodySchedule& schedule, std::uint64_t seed);
Scene make_checker_scene(std::uint64_t seed);

// Fixed geometry of the street scene, for placing cameras and objects (metres, world frame).
namespace street_layout {
inline constexpr double kLaneOffset = 2.0;      // lane centres at +-2 m from the centre line
inline constexpr double kRoadHalfWidth = 6.0;   // carriageway |y| <= 6 (parking at 4..6)
inline constexpr double kSidewalkOuter = 9.0;   // sidewalks 6..9 m, facades from 9 m
inline constexpr double kSidewalkHeight = 0.15;
inline constexpr double kMainWest = -130.0;     // main street x range, closed by buildings
inline constexpr double kMainEast = 430.0;
inline constexpr double kCrossX = 300.0;        // centre line of the cross street (runs to -y)
inline constexpr double kCrossSouth = -715.0;   // cross street end, closed by a building
}  // namespace street_layout

}  // namespace bolo::sim::scene
