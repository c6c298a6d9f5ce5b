#pragma once
// Direct sparse monocular visual odometry with a microbolometer photometric model.
//
// Per frame: pyramid -> (initialisation | coarse-to-fine direct alignment against the active
// points of the keyframe window) -> tau refinement (ir modes) -> epipolar depth search for
// immature points -> keyframe decision -> (new keyframe: point selection, retirement of the
// oldest, sliding-window bundle adjustment). Single-threaded, deterministic, and all storage
// comes from one caller-provided arena sized by arena_bytes().

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/vo/carry_model.hpp"
#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct FrameInput {
  std::span<const std::uint16_t> raw;        // width x height raw counts
  std::span<const std::uint16_t> corrected;  // ir_loop: the corrector's output; else empty
  double t_s = 0;
  double exposure_s = 0;      // this frame's exposure
  double readout_prev_s = 0;  // readout after the previous frame
  // The previous raw frame is not this frame's predecessor on the sensor: first frame, shutter
  // event, dropped frames. The carry-over term is then unknown for this frame.
  bool chain_broken = false;
  // A shutter (flat-field) event completed before this frame: the pixels settled on the uniform
  // shutter, so the frame is the scene's step response, whose contrast measures tau (ir modes).
  // Implies chain_broken.
  bool shutter_event = false;
};

// duplicate: the frame repeats the previous one bit for bit (a camera or link that sends a frame
// twice); it is skipped, and the frame after it has no known carry-over (its sensor predecessor
// was never delivered).
enum class TrackingState : std::uint8_t { initialising, tracking, lost, duplicate };
const char* to_string(TrackingState state);

// No keyframe (a frame without a pose, a pose not tied to one).
inline constexpr std::uint32_t kNoKeyframe = 0xffffffffu;

// Where a pose stands in the map: its keyframe and the camera's pose in that keyframe's frame
// (camera-to-keyframe, so the keyframe's pose times it is the camera-to-world pose). Carried on
// the keyframe's later poses (Odometry::retired_keyframes, window_keyframes) it gives the pose as
// the window refined the map after the frame came: the trajectory DSO and ORB-SLAM write at the
// end of a run.
struct KeyframeTie {
  std::uint32_t keyframe = kNoKeyframe;
  Se3 T_kc;
};

struct FrameResult {
  TrackingState state = TrackingState::initialising;
  bool has_pose = false;
  Se3 T_wc;                       // camera-to-world
  bool keyframe = false;
  bool reinitialised = false;     // the map was restarted after losing track
  std::uint32_t tracked_points = 0;
  float residual_rms = 0;         // photometric, counts, over the inlier residuals
  Tau tau;                        // current estimate (ir modes; the initial value otherwise)
  // ir modes, a frame after a shutter event: tau from its step response (0 when not measured).
  double shutter_tau_s = 0;
  // The camera centre was held on its velocity before a look-around (VoConfig::scale_bridge):
  // only the rotation was tracked.
  bool centre_held = false;
  // With a pose: the keyframe it was tracked against (the newest; the frame's own when it became
  // one, the map's first while initialising).
  KeyframeTie tie;
};

// A pose given to a frame after it was processed (camera-to-world, at the frame's t_s).
struct TimedPose {
  double t_s = 0;
  Se3 T_wc;
  KeyframeTie tie;
};

// A keyframe's pose (camera-to-world) as the window last adjusted it.
struct KeyframePose {
  std::uint32_t id = 0;
  double t_s = 0;
  Se3 T_wc;
};

struct WorldPoint {
  float x = 0, y = 0, z = 0, intensity = 0;
};

struct State;

class Odometry {
 public:
  static std::size_t arena_bytes(const VoConfig& config);
  // `arena` must hold arena_bytes(config) bytes and outlive the object. ok() is false when the
  // configuration is invalid (invalid_reason) or the arena too small.
  Odometry(const VoConfig& config, std::span<std::byte> arena);
  bool ok() const { return state_ != nullptr; }

  FrameResult process(const FrameInput& in);
  Tau tau() const;
  // tau_c's standard error, seconds (ir modes, tau estimated; 0 while unknown): see
  // tau_standard_error in tau_estimator.hpp.
  double tau_standard_error() const;
  // The intensity scale the thresholds use (VoConfig::intensity_scale; measured after the
  // first frames when configured 0).
  float intensity_scale() const;

  // Active points of the keyframes retired by the last process() call, in world coordinates.
  std::span<const WorldPoint> retired_points() const;
  // The keyframes that left the window in the last process() call, at their last poses.
  std::span<const KeyframePose> retired_keyframes() const;
  // The keyframes in the window at their current poses; returns how many were written.
  std::size_t window_keyframes(std::span<KeyframePose> out) const;
  // Active points of the keyframes still in the window; returns how many were written.
  std::size_t window_points(std::span<WorldPoint> out) const;
  std::uint32_t keyframes_created() const;
  // The frames an initialisation took before the frame that completed it (the map's first
  // keyframe first), posed in the basin it completed in; non-empty only after the process() call
  // that completed it. Frames solved before its solves last disagreed on the basin are left out.
  std::span<const TimedPose> initialisation_poses() const;

 private:
  State* state_ = nullptr;
};

}  // namespace bolo::vo
