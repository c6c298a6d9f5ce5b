#pragma once
// The initialiser (initializer.cpp): a map from the first keyframe and a later frame.

#include <array>
#include <cstdint>

#include "bolo/vo/config.hpp"
#include "bolo/vo/odometry.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct BrightnessTrack;
struct CurrentFrame;
struct Keyframe;
struct MapCore;
struct MotionModel;
struct TrackingReference;

// An initialisation that has taken this many frames without completing starts afresh.
constexpr std::uint32_t kMaxInitFrames = 90;

// A frame the initialisation took: its pose relative to the first keyframe (the frame's T_cw times
// the keyframe's T_wc) as that step solved it, in the map's scale.
struct SolvedFrame {
  double t_s = 0;
  Se3 M;
};

struct InitialiserState {
  bool initialised = false;
  std::uint32_t frames = 0;  // frames tried against the first keyframe
  std::array<SolvedFrame, kMaxInitFrames> solved;
  std::uint32_t agreed_since = 0;  // the first solved frame after the last on which the solves' basins differed
  // Once it completes: the first keyframe and the frames solved before the completing one, as
  // world poses in its basin (Odometry::initialisation_poses).
  std::array<TimedPose, kMaxInitFrames> poses;
  std::uint32_t pose_count = 0;
  bool completed_now = false;  // by the frame being processed
  // The map began as a rotation about the camera's centre and the camera has not translated since:
  // none of its points has a depth of its own.
  bool map_without_baseline = false;
  Se3 map_origin;  // world to camera at the map's first keyframe
};

// One frame f against the map's first keyframe: refines the relative pose and the keyframe's
// inverse depths, and sets the camera's pose, motion model and brightness for f. Returns true
// once the map is initialised (its points active, the tracking reference stale).
bool initialise_step(MapCore& s, InitialiserState& init, const CurrentFrame& f, MotionModel& motion,
                     BrightnessTrack& brightness, TrackingReference& ref);
// A new map starts from `host`, just made from the current frame: its points at inverse depth 1,
// the initialiser counting afresh.
void start_initialisation(InitialiserState& init, Keyframe& host);
// Clears map_without_baseline once the tracked camera has moved as far from the map's first
// keyframe as the initialisation's baseline.
void follow_map_baseline(InitialiserState& init, const MotionModel& motion, const VoConfig& cfg);
// The baseline a map needs, as the flow it causes at the typical depth (pixels, level 0).
double baseline_flow_needed(const VoConfig& cfg);

}  // namespace bolo::vo
