#pragma once
// The tracker (tracker.cpp): direct alignment of a frame against the tracking reference.

#include <cstdint>
#include <span>

#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct CurrentFrame;
struct MapCore;
struct ScaleBridge;

// A window point as the tracker sees it: reprojected into the newest keyframe (the tracking
// reference), so the patterns compared with the frame come from the keyframe nearest to it.
struct RefPoint {
  float u = 0, v = 0, idepth = 1;  // in the reference keyframe, level 0
  std::uint32_t source = 0;        // host slot << 16 | point index
  bool in_view = false;            // tracking: visible at the start of the current pyramid level
  float refv[kPattern] = {};       // the reference keyframe's pattern at the current level
};

// The tracking reference: the window's active points in the newest keyframe.
struct TrackingReference {
  std::span<RefPoint> points;
  std::uint32_t count = 0;
  double mean_idepth = 0;  // of its points: how far a pose step moves them
  bool dirty = true;       // keyframes, poses or depths changed since it was built
};

struct TrackResult {
  Se3 T_cw;
  double a = 0, b = 0;
  float rms = 0;
  double mean_energy = 0;  // robust energy per point of the last level's point set
  std::uint32_t visible = 0, inliers = 0;
  std::uint32_t level = 0;  // the last level tracked
  bool ok = false;
};
// Brightness parameters a frame may change that the photometric mode otherwise holds (ir modes:
// a frame without its sensor predecessor has an unknown carry-over, so its raw counts are
// tracked with a free gain and offset; the frame after it, whose scene estimate has the camera's
// offset since then, with a free offset).
struct FreeBrightness {
  bool gain = false, offset = false;
};
// Coarse to fine down to `last_level` (0: the full tracking; above 0: a quick look at a guess,
// mean_energy and the pose at that level only, ok = finite). `resume`: the result of an earlier
// call with the same guess, a, b and free_offset that stopped at resume->level; the levels down
// to it are not repeated (the tracking continues from its pose: the same result as a full call).
// The frame is f, the window map's (whose points' inlier flags it sets); the scale bridge may hold
// the camera centre (translation_prior_weight). Rebuilds ref first when it is dirty.
TrackResult track_frame(TrackingReference& ref, MapCore& map, const CurrentFrame& f, const ScaleBridge& bridge,
                        Se3 guess, double a, double b, FreeBrightness free, std::uint32_t last_level = 0,
                        const TrackResult* resume = nullptr);
// Rebuilds the tracking reference from the window's active points.
void build_tracking_reference(TrackingReference& ref, const MapCore& map);

}  // namespace bolo::vo
