#include "bolo/simulate_scene.hpp"

#include <cmath>
#include <memory>

#include "bolo/errors.hpp"
#include "bolo/sim/demo_scene.hpp"
#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"

namespace bolo::cli {
namespace {

constexpr double kHorizontalFovDeg = 50.0;

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

SimulatedScene demo_scene(const std::string& trajectory, const sim::SimulationInfo& info) {
  if (!trajectory.empty())
    fail("--trajectory ", trajectory, ": the demo scene is a flat moving pattern without a camera path");
  // Levels relative to the 300 K level, so every bit depth sees a usable scene.
  sim::DemoSceneOptions o;
  const double ref = info.reference_level;
  o.background = 0.75 * ref;
  o.gradient = 0.1 * ref;
  o.bar_contrast = -0.08 * ref;
  o.hot_contrast = 0.5 * ref;
  o.speed_px_per_s = 2.0 * info.width;  // two widths a second: strong ghosting
  const std::uint32_t w = info.width, h = info.height;
  return {[w, h, o](double t, std::span<float> out) { sim::render_demo_scene(w, h, t, o, out); },
          std::nullopt, {}, ""};
}

std::string default_trajectory(const std::string& scene) {
  if (scene == "lab") return "blackbody";
  if (scene == "checker") return "blackbody";  // front-on to the checker wall
  return "drive";
}

}  // namespace

std::string simulated_scene_names() { return "demo, " + join(sim::scene::scene_names()); }
std::string simulated_trajectory_names() { return join(sim::scene::trajectory_names()); }

SimulatedScene make_simulated_scene(const std::string& scene_name, const std::string& trajectory_name,
                                    const sim::SensorPreset& preset, const sim::SimulationInfo& info,
                                    unsigned supersample, const std::vector<double>& distortion) {
  if (scene_name == "demo") {
    if (!distortion.empty()) fail("--distortion: the demo scene is a flat pattern without a lens");
    return demo_scene(trajectory_name, info);
  }
  bool known = false;
  for (const auto& n : sim::scene::scene_names()) known = known || n == scene_name;
  if (!known) fail("--scene ", scene_name, ": unknown scene (known: ", simulated_scene_names(), ")");
  const std::string path = trajectory_name.empty() ? default_trajectory(scene_name) : trajectory_name;
  bool known_path = false;
  for (const auto& n : sim::scene::trajectory_names()) known_path = known_path || n == path;
  if (!known_path)
    fail("--trajectory ", path, ": unknown trajectory (known: ", simulated_trajectory_names(), ")");

  auto trajectory = std::make_shared<sim::scene::Trajectory>(sim::scene::make_trajectory(path, info.seed));
  if (trajectory->scene() != scene_name && scene_name != "checker")
    fail("--trajectory ", path, ": laid out for the ", trajectory->scene(), " scene, not ", scene_name);
  sim::scene::Camera camera(info.width, info.height, kHorizontalFovDeg);
  // OpenCV's order, as cv::calibrateCamera writes the coefficients.
  double* const coefficient[8] = {&camera.k1, &camera.k2, &camera.p1, &camera.p2,
                                  &camera.k3, &camera.k4, &camera.k5, &camera.k6};
  if (distortion.size() > 8)
    fail("--distortion: at most 8 values (k1,k2,p1,p2,k3,k4,k5,k6), got ", distortion.size());
  for (std::size_t k = 0; k < distortion.size(); ++k) {
    if (!std::isfinite(distortion[k])) fail("--distortion: value ", k + 1, " is not finite");
    *coefficient[k] = distortion[k];
  }
  if (const char* why = sim::scene::distortion_problem(camera)) fail("--distortion: ", why);
  sim::scene::RenderOptions render_options;
  render_options.supersample = supersample;
  auto renderer = std::make_shared<sim::scene::Renderer>(sim::scene::make_scene(scene_name, info.seed), camera,
                                                         render_options);
  // Kelvin to the sensor's steady-state counts, linear about 300 K and scaled to the bit depth.
  const double scale = std::ldexp(1.0, static_cast<int>(info.bits) - 14);
  const double level = info.reference_level, per_kelvin = preset.counts_per_kelvin * scale;
  SimulatedScene s;
  s.input = [renderer, trajectory, level, per_kelvin](double t, std::span<float> out) {
    renderer->render(trajectory->pose(t), t, out);
    for (float& v : out) v = static_cast<float>(level + per_kelvin * (v - 300.0));
  };
  s.camera = camera.to_json();
  s.pose_line = [trajectory](double t) { return sim::scene::to_tum(t, trajectory->pose(t)); };
  s.trajectory = path;
  return s;
}

}  // namespace bolo::cli
