// The `lab` and `checker` scenes.
#include "bolo/sim/scene/scene.hpp"
#include "random.hpp"

namespace bolo::sim::scene {
namespace {

Quad rect(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v, double u0, double u1,
          double v0, double v1, std::size_t mat, std::uint64_t seed) {
  Quad q;
  q.origin = origin;
  q.u_axis = u;
  q.v_axis = v;
  q.u_min = u0;
  q.u_max = u1;
  q.v_min = v0;
  q.v_max = v1;
  q.material = mat;
  q.seed = seed;
  return q;
}

}  // namespace

Scene make_lab_scene(const BlackbodySchedule& schedule, std::uint64_t seed) {
  schedule.validate();
  detail::Rng rng(seed ^ 0x1ABull);
  Scene s;
  s.name = "lab";
  s.viewpoint = Eigen::Vector3d(0.0, 0.0, 1.2);
  s.viewpoint_yaw = 0.0;
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();

  Material wall;
  wall.name = "lab wall";
  wall.base_k = 295.15;
  wall.noise_k = 0.3;
  wall.noise_scale_m = 1.5;
  wall.detail_k = 0.08;
  wall.detail_scale_m = 0.2;
  wall.seed = rng.next();
  const std::size_t wall_m = s.add_material(wall);
  Material floor = wall;
  floor.name = "lab floor";
  floor.base_k = 294.4;
  floor.pattern = Tiles{0.5, 0.01, -0.3, 0.15};
  floor.seed = rng.next();
  const std::size_t floor_m = s.add_material(floor);
  Material ceiling = wall;
  ceiling.name = "lab ceiling";
  ceiling.base_k = 296.0;
  ceiling.seed = rng.next();
  const std::size_t ceiling_m = s.add_material(ceiling);
  Material housing;
  housing.name = "blackbody housing";
  housing.base_k = 297.0;
  housing.noise_k = 0.2;
  housing.seed = rng.next();
  const std::size_t housing_m = s.add_material(housing);
  Material target;
  target.name = "blackbody target";
  target.base_k = schedule.plateaus_k.front();
  target.base_of_t = [schedule](double t) { return schedule.temperature(t); };
  target.seed = rng.next();
  const std::size_t target_m = s.add_material(target);

  // A 6 m x 6 m x 3 m room around the origin.
  s.add_quad(rect({0, 0, 0}, X, Y, -3, 3, -3, 3, floor_m, rng.next()));
  s.add_quad(rect({0, 0, 3}, X, Y, -3, 3, -3, 3, ceiling_m, rng.next()));
  s.add_quad(rect({3, 0, 0}, Y, Z, -3, 3, 0, 3, wall_m, rng.next()));
  s.add_quad(rect({-3, 0, 0}, Y, Z, -3, 3, 0, 3, wall_m, rng.next()));
  s.add_quad(rect({0, 3, 0}, X, Z, -3, 3, 0, 3, wall_m, rng.next()));
  s.add_quad(rect({0, -3, 0}, X, Z, -3, 3, 0, 3, wall_m, rng.next()));
  // The blackbody: a 2 m x 2 m emitter 0.4 m in front of the viewpoint (fills up to ~136 deg
  // of field of view), on a housing.
  s.add_quad(rect({0.399, 0, 1.2}, -Y, Z, -1.0, 1.0, -1.0, 1.0, target_m, rng.next()));
  Box b;
  b.lo = Eigen::Vector3d(0.4, -1.1, 0.1);
  b.hi = Eigen::Vector3d(0.7, 1.1, 2.3);
  b.material = housing_m;
  b.seed = rng.next();
  s.add_box(b);
  return s;
}

Scene make_checker_scene(std::uint64_t seed) {
  detail::Rng rng(seed ^ 0xC4ECull);
  Scene s;
  s.name = "checker";
  s.viewpoint = Eigen::Vector3d(0.0, 0.0, 1.2);
  s.viewpoint_yaw = 0.0;
  Material ground;
  ground.name = "checker ground";
  ground.pattern = Checker{1.0, 275.0, 295.0};
  ground.seed = rng.next();
  const std::size_t ground_m = s.add_material(ground);
  Material wall;
  wall.name = "checker wall";
  wall.pattern = Checker{0.25, 280.0, 310.0};
  wall.seed = rng.next();
  const std::size_t wall_m = s.add_material(wall);
  Quad g;
  g.material = ground_m;
  g.seed = rng.next();
  s.add_quad(g);
  // 4 m x 3 m wall at x = 2.5 facing the viewpoint; u to the viewer's right (-y), v up.
  s.add_quad(rect({2.5, 0, 0}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), -2, 2, 0, 3, wall_m, rng.next()));
  return s;
}

}  // namespace bolo::sim::scene
