#pragma once
// What the frame loop itself keeps (odometry.cpp): its keyframe and loss bookkeeping, the new
// keyframes' point selection, and the points retired from the window.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/vo/config.hpp"
#include "bolo/vo/odometry.hpp"
#include "bolo/vo/point_selector.hpp"

namespace bolo::vo {

struct BaSystem;
struct BrightnessTrack;
struct CurrentFrame;
struct Keyframe;
struct MapCore;
struct MarginalPrior;
struct MotionModel;
struct NoiseEstimate;
struct TrackingReference;

struct FrameLoop {
  std::uint32_t lost_frames = 0;
  std::uint32_t frames_since_kf = 0, inliers_after_kf = 0;
  double since_kf_s = 0;  // the time those frames span
  float last_rms = 0;
};

// Where a new keyframe's points go.
struct KeyframeSelection {
  std::span<std::uint8_t> occupied;
  std::span<PixelPoint> candidates;
  SelectorScratch scratch;
};

// The keyframes that left the window with this frame and their points (Odometry::retired_points,
// retired_keyframes).
struct RetiredPoints {
  std::span<WorldPoint> points;
  std::size_t count = 0;
  KeyframePose keyframes[kMaxKeyframes];
  std::uint32_t keyframe_count = 0;
};

// What making a keyframe reads besides the map (the current frame, the camera's pose, the frame's
// brightness) and writes (the brightness's offset step restarts, the tracking reference goes
// stale, the point selection's buffers).
struct KeyframeParts {
  const CurrentFrame& frame;
  const MotionModel& motion;
  BrightnessTrack& brightness;
  TrackingReference& ref;
  KeyframeSelection& selection;
};

// A free keyframe slot; a full window first retires a keyframe (keyframe_to_retire): its active
// points go to `retired` and, where the prior is built, its information to the prior.
std::uint32_t new_keyframe_slot(MapCore& s, RetiredPoints& retired, BaSystem& ba, MarginalPrior& prior);
// Appends a keyframe's active points (world coordinates) to the retired-points output.
void retire_points(RetiredPoints& retired, const Keyframe& old, const Camera& camera);
// The current frame becomes the newest keyframe, in `slot`; with select_points_now, with new
// immature points where the window's active points do not land.
void make_keyframe(MapCore& s, const KeyframeParts& parts, std::uint32_t slot, bool select_points_now);
// Sets s.intensity from the current frame's pixel noise, for VoConfig::intensity_scale 0; leaves
// it pending while the noise cannot be measured yet.
void measure_intensity_scale(MapCore& s, NoiseEstimate& noise, const CurrentFrame& f);

}  // namespace bolo::vo
