#pragma once
// The core every part of the VO shares (State derives from it): the configuration, the window's
// keyframes and their points, the scratch buffer, the intensity scale; and the frame-timing rules
// that say whether two images share a brightness level.

#include <cmath>
#include <cstdint>
#include <span>

#include "bolo/vo/config.hpp"
#include "bolo/vo/image.hpp"
#include "bolo/vo/odometry.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

// `leaving`: inside the window BA only, an active point its last trial found to fit most keyframes
// badly; it leaves the map if that trial is accepted.
enum class PointStatus : std::uint8_t { empty, immature, active, leaving };

struct Point {
  float u = 0, v = 0;  // host pixel, level 0
  float idepth = 1, idepth_min = 0, idepth_max = -1;  // max < 0: unbounded
  float energy = 0;      // last pattern energy when tracked
  float quality = 0;     // immature: second-best / best energy of the last search
  PointStatus status = PointStatus::empty;
  std::uint8_t good = 0, bad = 0;
  std::uint8_t still_matches = 0;  // immature: frames it matched where no baseline could place it
  bool inlier = false;   // in the last tracking
};

struct Keyframe {
  bool used = false;
  std::uint32_t id = 0;
  Se3 T_cw;
  double a = 0, b = 0;  // affine brightness, absolute
  double t_s = 0, exposure_s = 0, readout_prev_s = 0;
  bool chain_ok = false;
  Pyramid pyramid;
  std::span<Point> points;
  std::uint32_t count = 0;  // points used in `points`
  bool settled = true;  // made kTimingSettleFrames or more after a change of timing (same_level)
};

// A camera-to-world pose as it stands in keyframe kf's frame (KeyframeTie).
inline KeyframeTie tie_to(const Keyframe& kf, const Se3& T_wc) { return {kf.id, kf.T_cw * T_wc}; }

// The ir modes: the tracking image is the scene estimate of the two-frame carry-over model.
inline bool uses_carry_model(const VoConfig& c) {
  return c.photometric == Photometric::ir || c.photometric == Photometric::ir_loop;
}
// Frames from a change of exposure or readout (the change frame itself first) whose image holds
// part of the carry-over of the frames before the change, which the scene estimate removes right
// only at the true tau: it decays by alpha (0.4-0.6 at 60 Hz) a frame, to a few per cent of its
// first-frame share by then.
inline constexpr std::uint32_t kTimingSettleFrames = 4;
// More than 1 %: timings read from a camera's timestamps jitter.
inline bool timing_differs(double before_s, double now_s) {
  return before_s > 0 && now_s > 0 && std::abs(now_s - before_s) > 0.01 * before_s;
}

// The part of the VO's state every part uses. Everything here lives in the arena.
struct MapCore {
  VoConfig cfg;
  Keyframe kf[kMaxKeyframes];
  std::uint32_t order[kMaxKeyframes] = {};  // slots, oldest first
  std::uint32_t kf_count = 0;
  std::uint32_t kf_created = 0;
  // Per window point the window BA's rows (window_ba.cpp), or the initialiser's 8 floats a point
  // plus two depth backups; between those, scratch for medians (depth search, odometry).
  std::span<float> scratch;
  float intensity = 1;              // the intensity scale in use (VoConfig::intensity_scale)
  bool intensity_pending = false;   // to be measured from the pixel noise
  std::uint32_t raw_frames = 0;     // frames loaded while it is pending
};

// The configured thresholds in counts times the intensity scale (VoConfig::intensity_scale).
inline float huber_threshold(const MapCore& s) { return s.cfg.huber_counts * s.intensity; }
inline float gradient_weight_c(const MapCore& s) { return s.cfg.gradient_c * s.intensity; }

}  // namespace bolo::vo
