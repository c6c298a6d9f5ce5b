#pragma once
// Frames of the street scene rendered in-process at ground-truth poses (no sensor model, no
// noise), with the true depth of any pixel: the fixture of the VO's unit tests.

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"
#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::test {

struct RenderedSequence {
  std::uint32_t width = 160, height = 120;
  sim::scene::Camera camera{160, 120, 50.0};
  sim::scene::Renderer renderer;
  sim::scene::Trajectory trajectory;

  // `supersample` n: n x n rays per pixel (1 = what `bolo simulate` renders: aliased).
  RenderedSequence(const char* scene, const char* trajectory_name, std::uint32_t w, std::uint32_t h,
                   unsigned supersample = 1, std::uint64_t seed = 1)
      : width(w), height(h), camera(w, h, 50.0),
        renderer(sim::scene::make_scene(scene, seed), camera, {1, supersample}),
        trajectory(sim::scene::make_trajectory(trajectory_name, seed)) {}

  vo::Camera intrinsics() const {
    const auto j = camera.to_json();
    return {j.at("fx").template get<float>(), j.at("fy").template get<float>(), j.at("cx").template get<float>(), j.at("cy").template get<float>()};
  }
  // Counts as the simulator's generic preset makes them: 8000 + 40 per kelvin above 300 K.
  std::vector<std::uint16_t> frame(double t) const {
    const std::vector<float> k = renderer.render(trajectory.pose(t), t);
    std::vector<std::uint16_t> out(k.size());
    for (std::size_t i = 0; i < k.size(); ++i) out[i] = static_cast<std::uint16_t>(std::lround(8000.0 + 40.0 * (k[i] - 300.0)));
    return out;
  }
  // World-to-camera at time t.
  vo::Se3 T_cw(double t) const {
    const auto pose = trajectory.pose(t);
    vo::Se3 T_wc;
    T_wc.R = pose.orientation.toRotationMatrix();
    T_wc.t = pose.position;
    return T_wc.inverse();
  }
  // Depth (camera z) of the surface seen at a pixel; < 0 for sky.
  double depth(double t, double u, double v) const {
    const auto hit = renderer.trace_pixel(trajectory.pose(t), t, Eigen::Vector2d(u, v));
    if (hit.kind == sim::scene::RayHit::Kind::sky) return -1;
    return trajectory.pose(t).to_camera(hit.point).z();
  }
};

}  // namespace bolo::test
