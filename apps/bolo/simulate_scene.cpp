#include "bolo/simulate_scene.hpp"

#include "bolo/errors.hpp"
#include "bolo/sim/demo_scene.hpp"

namespace bolo::cli {

std::string simulated_scene_names() { return "demo"; }

SimulatedScene make_simulated_scene(const std::string& scene, const std::string& trajectory,
                                    const sim::SensorPreset& preset, const sim::SimulationInfo& info) {
  (void)preset;
  if (scene == "demo") {
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
  fail("--scene ", scene, ": unknown scene (known: ", simulated_scene_names(), ")");
}

}  // namespace bolo::cli
