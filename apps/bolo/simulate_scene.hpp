#pragma once
// The scenes `bolo simulate` can render, as the simulator's input (steady-state counts), with the
// camera.json and poses.tum that go with them.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/sim/sensor_preset.hpp"
#include "bolo/sim/simulator.hpp"

namespace bolo::cli {

struct SimulatedScene {
  sim::InputSampler input;
  std::optional<nlohmann::json> camera;               // camera.json, for 3D scenes
  std::function<std::string(double t_s)> pose_line;   // one poses.tum line with its newline
  std::string trajectory;                             // as used
};

// Throws bolo::cli::Error naming the unknown scene or trajectory and listing the known ones.
// `supersample` n: n x n rays per pixel for the 3D scenes (1: one ray through the pixel centre).
// `distortion`: the lens's k1, k2, p1, p2 (Brown-Conrady, camera.json), fewer values meaning 0;
// refused unless the distortion is one-to-one over the image.
SimulatedScene make_simulated_scene(const std::string& scene, const std::string& trajectory,
                                    const sim::SensorPreset& preset, const sim::SimulationInfo& info,
                                    unsigned supersample = 1, const std::vector<double>& distortion = {});
std::string simulated_scene_names();
std::string simulated_trajectory_names();

}  // namespace bolo::cli
