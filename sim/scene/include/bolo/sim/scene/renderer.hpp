#pragma once
// Ray casting renderer: per pixel, undistort -> ray -> nearest hit -> material temperature ->
// atmosphere; rays that hit nothing see the sky. Output: scene temperature in kelvin, float,
// row-major W x H.
//
// Motion during the exposure is the caller's: render one sub-sample per time and integrate.
// Results are bit-identical for any thread count (each pixel is computed independently).

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "bolo/sim/scene/camera.hpp"
#include "bolo/sim/scene/pose.hpp"
#include "bolo/sim/scene/scene.hpp"

namespace bolo::sim::scene {

struct RenderOptions {
  unsigned threads = 0;      // 0: std::thread::hardware_concurrency(); 1: the calling thread
  unsigned supersample = 1;  // n x n rays per pixel on a regular sub-pixel grid, averaged
};

// What one ray sees.
struct RayHit {
  enum class Kind { sky, quad, box };
  Kind kind = Kind::sky;
  std::size_t index = 0;     // into scene.quads or scene.boxes
  bool moving = false;       // the box has a motion
  double distance = kInfinity;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world
  SurfacePoint surface;                             // object frame
  double surface_k = 0.0;      // material temperature at the hit (sky: the sky temperature)
  double temperature_k = 0.0;  // what the camera sees: surface_k through the atmosphere
};

class Renderer {
 public:
  // Copies the scene (validating it) and builds its acceleration structure and the camera's
  // ray table. Throws std::invalid_argument on a bad scene, camera or options.
  Renderer(Scene scene, const Camera& camera, RenderOptions options = {});
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Scene temperature (K) per pixel for camera-to-world `pose` at time t; out.size() == W*H.
  // Thread-safe (const, no shared mutable state).
  void render(const Pose& pose, double t, std::span<float> out) const;
  std::vector<float> render(const Pose& pose, double t) const;

  // One ray (world origin, world direction of any length) at time t.
  RayHit trace(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t) const;
  // The ray through pixel (u, v) (centre of the top-left pixel = (0, 0)).
  RayHit trace_pixel(const Pose& pose, double t, const Eigen::Vector2d& pixel) const;

  const Scene& scene() const;
  const Camera& camera() const;
  const RenderOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bolo::sim::scene
