#pragma once
// What the frame loop itself keeps (odometry.cpp): its keyframe and loss bookkeeping, the new
// keyframes' point selection, and the points retired from the window.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/vo/odometry.hpp"
#include "bolo/vo/point_selector.hpp"

namespace bolo::vo {

struct State;
struct Keyframe;

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

// The points that left the window with this frame (Odometry::retired_points).
struct RetiredPoints {
  std::span<WorldPoint> points;
  std::size_t count = 0;
};

std::uint32_t new_keyframe_slot(State& s);
// Appends a keyframe's active points (world coordinates) to the retired-points output.
void retire_points(State& s, const Keyframe& old);
void make_keyframe(State& s, std::uint32_t slot, bool select_points_now);
// Sets s.intensity from the current frame's pixel noise, for VoConfig::intensity_scale 0; leaves
// it pending while the noise cannot be measured yet.
void measure_intensity_scale(State& s);

}  // namespace bolo::vo
