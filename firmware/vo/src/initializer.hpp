#pragma once
// The initialiser (initializer.cpp): a map from the first keyframe and a later frame.

#include <cstdint>

#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct State;

struct InitialiserState {
  bool initialised = false;
  std::uint32_t frames = 0;  // frames tried against the first keyframe
  // The map began as a rotation about the camera's centre and the camera has not translated since:
  // none of its points has a depth of its own.
  bool map_without_baseline = false;
  Se3 map_origin;  // world to camera at the map's first keyframe
};

// Returns true once the map is initialised from the first keyframe and the current frame.
bool initialise_step(State& s);
void start_initialisation(State& s);
// Clears map_without_baseline once the tracked camera has moved as far from the map's first
// keyframe as the initialisation's baseline.
void follow_map_baseline(State& s);
// The baseline a map needs, as the flow it causes at the typical depth (pixels, level 0).
double baseline_flow_needed(const VoConfig& cfg);

}  // namespace bolo::vo
