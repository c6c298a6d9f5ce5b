#pragma once
// Named camera trajectories, continuous in time (poses are defined, and continuous, for every
// t; sub-frame samples are smooth). Poses are camera-to-world (see pose.hpp).

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bolo/sim/scene/pose.hpp"

namespace bolo::sim::scene {

class Trajectory {
 public:
  Trajectory(std::string name, std::string scene, double duration_s,
             std::function<Pose(double t)> pose);
  Pose pose(double t) const { return pose_(t); }
  const std::string& name() const { return name_; }
  // The scene the trajectory is laid out for ("street", "lab").
  const std::string& scene() const { return scene_; }
  // A sensible recording length (s); poses exist beyond it too.
  double duration_s() const { return duration_s_; }

 private:
  std::string name_;
  std::string scene_;
  double duration_s_;
  std::function<Pose(double)> pose_;
};

std::vector<std::string> trajectory_names();  // the names make_trajectory() knows, in help order

// A named trajectory, deterministic from the seed (street trajectories use street_layout):
//   drive      car-mounted camera, 1.4 m high, in the right lane of the main street at
//              ~8-12 m/s, slowing to ~5 m/s for one right turn into the cross street at
//              t ~ 30 s, small vertical/pitch/roll oscillations; comes to a smooth stop before
//              the end of the cross street (~100 s) and stays there
//   handheld   walking (~1.35 m/s) on the south sidewalk, back and forth, with 6-DoF hand shake,
//              gait bob and sway, and three fast look-arounds (up to ~500 deg/s) every 30 s
//   static     tripod on the south sidewalk looking across the street; cars pass
//   pan        tripod at the T junction, rotating about the vertical at a constant 30 deg/s
//   blackbody  fixed, looking at the lab scene's target (see BlackbodySchedule)
// Throws std::invalid_argument naming the unknown trajectory and listing the valid ones.
Trajectory make_trajectory(const std::string& name, std::uint64_t seed);

// TUM lines for the given times (each line as to_tum(t, pose)).
std::string to_tum(const Trajectory& trajectory, std::span<const double> times);

}  // namespace bolo::sim::scene
