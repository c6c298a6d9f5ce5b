// Trajectories: continuity, speeds, layout, TUM output, names, determinism.
#include <cmath>
#include <sstream>

#include <catch2/catch.hpp>

#include "bolo/sim/scene/scene.hpp"
#include "bolo/sim/scene/trajectory.hpp"

using namespace bolo::sim::scene;

namespace {
Eigen::Vector3d forward(const Pose& p) { return p.orientation * Eigen::Vector3d::UnitZ(); }
}  // namespace

TEST_CASE("camera_pose and look_at: camera x right, y down, z forward in a z-up world", "[scene][pose]") {
  const Pose p = camera_pose({1, 2, 3}, 0.0, 0.0, 0.0);
  CHECK((p.orientation * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm() < 1e-12);
  CHECK((p.orientation * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm() < 1e-12);
  CHECK((p.orientation * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitZ()).norm() < 1e-12);
  CHECK((p.to_world({0, 0, 2}) - Eigen::Vector3d(3, 2, 3)).norm() < 1e-12);
  CHECK((p.to_camera(p.to_world({0.3, -0.2, 5})) - Eigen::Vector3d(0.3, -0.2, 5)).norm() < 1e-12);
  // Yaw left, pitch up, roll: right side down.
  CHECK(forward(camera_pose({0, 0, 0}, M_PI / 2, 0)).y() == Approx(1.0));
  CHECK(forward(camera_pose({0, 0, 0}, 0, 0.2)).z() == Approx(std::sin(0.2)));
  CHECK((camera_pose({0, 0, 0}, 0, 0, 0.1).orientation * Eigen::Vector3d::UnitX()).z() < 0.0);
  const Pose l = look_at({0, 0, 1}, {5, 5, 1});
  const Pose c = camera_pose({0, 0, 1}, M_PI / 4, 0.0);
  CHECK(rotation_angle(l, c) < 1e-9);
  CHECK_THROWS_AS(look_at({0, 0, 0}, {0, 0, 5}), std::invalid_argument);
}

TEST_CASE("trajectories by name, an unknown name lists the valid ones", "[scene][trajectory]") {
  for (const auto& n : trajectory_names()) {
    const Trajectory t = make_trajectory(n, 1);
    CHECK(t.name() == n);
    CHECK(t.duration_s() > 0.0);
    CHECK_NOTHROW(make_scene(t.scene(), 1));
  }
  CHECK_THROWS_WITH(make_trajectory("orbit", 1), Catch::Contains("'orbit'") && Catch::Contains("drive") &&
                                                     Catch::Contains("handheld") && Catch::Contains("flyover") && Catch::Contains("static") &&
                                                     Catch::Contains("pan") && Catch::Contains("blackbody"));
}

TEST_CASE("trajectories are continuous: a small dt gives a small pose change", "[scene][trajectory]") {
  for (const auto& n : trajectory_names()) {
    const Trajectory tr = make_trajectory(n, 9);
    double max_v = 0.0, max_w = 0.0;
    for (double t = -1.0; t < tr.duration_s() + 40.0; t += 0.0137) {
      for (double dt : {1e-3, 1e-5}) {
        const Pose a = tr.pose(t), b = tr.pose(t + dt);
        const double v = translation_distance(a, b) / dt, w = rotation_angle(a, b) / dt;
        max_v = std::max(max_v, v);
        max_w = std::max(max_w, w);
      }
    }
    INFO(n << ": max speed " << max_v << " m/s, max angular rate " << max_w * 180 / M_PI << " deg/s");
    CHECK(max_v < 14.0);
    CHECK(max_w < 12.0);  // < ~690 deg/s even in the handheld's fast look-arounds
  }
}

TEST_CASE("drive: ~v*t forward, one right turn into the cross street, stays on the road", "[scene][trajectory]") {
  namespace L = street_layout;
  const Trajectory d = make_trajectory("drive", 2);
  CHECK(d.scene() == "street");
  const Pose p0 = d.pose(0.0), p10 = d.pose(10.0);
  CHECK(p10.position.x() - p0.position.x() == Approx(100.0).margin(15.0));  // 8.5-11.5 m/s
  CHECK(std::abs(p10.position.y() - p0.position.y()) < 0.05);
  CHECK(forward(p10).x() > 0.99);
  for (double t = 0.5; t < 20.0; t += 0.5) {
    const double v = translation_distance(d.pose(t), d.pose(t + 0.01)) / 0.01;
    CHECK(v > 8.0);
    CHECK(v < 12.0);
  }
  // Straight on until the junction, heading -y along the cross street afterwards.
  const Pose late = d.pose(60.0);
  CHECK(forward(late).y() < -0.99);
  CHECK(late.position.x() == Approx(L::kCrossX - L::kLaneOffset).margin(0.05));
  // It comes to rest before the end of the cross street and stays there.
  const Pose rest = d.pose(200.0);
  CHECK(translation_distance(rest, d.pose(300.0)) < 1e-6);
  CHECK(rest.position.y() > L::kCrossSouth + 10.0);
  CHECK(rest.position.y() < L::kCrossSouth + 40.0);
  // Always on the carriageway, 1.3-1.5 m above it, never inside the kerb corner.
  double slowest_turn = 1e9;
  for (double t = 0.0; t < 120.0; t += 0.05) {
    const Eigen::Vector3d p = d.pose(t).position;
    const bool main = std::abs(p.y()) < L::kRoadHalfWidth - 3.0 && p.x() < L::kCrossX;
    const bool cross = std::abs(p.x() - L::kCrossX) < L::kRoadHalfWidth - 3.0 && p.y() < 0.0;
    const bool junction = std::abs(p.x() - L::kCrossX) < L::kRoadHalfWidth && std::abs(p.y()) < L::kRoadHalfWidth;
    INFO("t=" << t << " p=" << p.transpose());
    CHECK((main || cross || junction));
    CHECK(p.z() > 1.3);
    CHECK(p.z() < 1.5);
    const double corner = std::hypot(p.x() - (L::kCrossX - L::kRoadHalfWidth), p.y() + L::kRoadHalfWidth);
    CHECK(corner > 1.5);
    if (std::abs(forward(d.pose(t)).x()) < 0.9 && std::abs(forward(d.pose(t)).y()) < 0.9)
      slowest_turn = std::min(slowest_turn, translation_distance(d.pose(t), d.pose(t + 0.01)) / 0.01);
  }
  CHECK(slowest_turn < 7.0);  // slows down for the turn
}

TEST_CASE("handheld: walking speed on the sidewalk with shake and fast rotations", "[scene][trajectory]") {
  const Trajectory h = make_trajectory("handheld", 4);
  const double dist = translation_distance(h.pose(0.0), h.pose(20.0));
  CHECK(dist > 22.0);
  CHECK(dist < 32.0);
  double max_w = 0.0, max_shake = 0.0;
  for (double t = 0.0; t < 60.0; t += 0.01) {
    const Pose p = h.pose(t);
    CHECK(p.position.y() > -9.0);
    CHECK(p.position.y() < -6.5);
    max_w = std::max(max_w, rotation_angle(p, h.pose(t + 0.002)) / 0.002);
    max_shake = std::max(max_shake, std::abs(p.position.z() - 1.65));
  }
  CHECK(max_w > 3.0);   // fast look-arounds (> 170 deg/s)
  CHECK(max_shake > 0.01);
  CHECK(max_shake < 0.05);
}

TEST_CASE("static, pan and blackbody", "[scene][trajectory]") {
  const Trajectory s = make_trajectory("static", 0);
  CHECK(translation_distance(s.pose(0), s.pose(17.0)) == 0.0);
  CHECK(rotation_angle(s.pose(0), s.pose(17.0)) == 0.0);
  const Trajectory p = make_trajectory("pan", 0);
  for (double t : {0.0, 3.3, 11.0}) {
    CHECK(rotation_angle(p.pose(t), p.pose(t + 1.0)) * 180.0 / M_PI == Approx(30.0).epsilon(1e-9));
    CHECK(translation_distance(p.pose(t), p.pose(t + 1.0)) == 0.0);
  }
  const Trajectory b = make_trajectory("blackbody", 0);
  const Pose bp = b.pose(12.0);
  CHECK(b.scene() == "lab");
  CHECK((forward(bp) - Eigen::Vector3d::UnitX()).norm() < 1e-12);
  CHECK(translation_distance(bp, b.pose(0.0)) == 0.0);
}

TEST_CASE("TUM lines: 8 numbers, unit quaternions, and they parse back", "[scene][trajectory]") {
  const Trajectory h = make_trajectory("handheld", 3);
  std::vector<double> times;
  for (int i = 0; i < 300; ++i) times.push_back(i / 8.7);
  const std::string text = to_tum(h, times);
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    double v[8];
    for (double& x : v) REQUIRE(f >> x);
    std::string extra;
    CHECK_FALSE(f >> extra);
    CHECK(v[0] == Approx(times[n]).margin(1e-9));
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    CHECK(qn == Approx(1.0).margin(5e-9));
    CHECK(v[7] >= 0.0);
    const StampedPose sp = parse_tum_line(line);
    const Pose truth = h.pose(times[n]);
    CHECK(translation_distance(sp.pose, truth) < 1e-8);
    CHECK(rotation_angle(sp.pose, truth) < 1e-8);
    ++n;
  }
  CHECK(n == times.size());
  CHECK(text.back() == '\n');
  CHECK_THROWS_WITH(parse_tum_line("1 2 3"), Catch::Contains("8 numbers"));
  CHECK_THROWS_WITH(parse_tum_line("1 2 3 4 0 0 0 1 5"), Catch::Contains("8 numbers"));
  CHECK_THROWS_WITH(parse_tum_line("1 2 nan 4 0 0 0 1"), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(parse_tum_line("1 2 3 4 0 0 0 inf"), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(parse_tum_line("1 2 3 4 0 0 0 0"), Catch::Contains("zero length"));
}

TEST_CASE("trajectories are deterministic from the seed", "[scene][trajectory]") {
  const std::vector<double> times = {0.0, 0.5, 3.0, 17.25, 44.0};
  for (const char* n : {"drive", "handheld"}) {
    CHECK(to_tum(make_trajectory(n, 7), times) == to_tum(make_trajectory(n, 7), times));
    CHECK(to_tum(make_trajectory(n, 7), times) != to_tum(make_trajectory(n, 8), times));
  }
}
