#pragma once
// The VO's working state: the shared core (MapCore: configuration, keyframes, points, scratch)
// and one part per owner, each declared next to the code that owns it. Everything here lives in
// the arena (lay_out()).

#include <cstdint>

#include "bolo/vo/carry_model.hpp"
#include "bolo/vo/config.hpp"
#include "depth_search.hpp"
#include "frame_loop.hpp"
#include "frame_state.hpp"
#include "initializer.hpp"
#include "keyframe_retirement.hpp"
#include "map.hpp"
#include "motion_model.hpp"
#include "noise_estimator.hpp"
#include "photometric_math.hpp"
#include "scale_bridge.hpp"
#include "tau_estimator.hpp"
#include "tracker.hpp"
#include "window_ba.hpp"

namespace bolo::vo {

// One per VO, in the arena: its parts stay grouped by owner rather than ordered for the bytes of
// padding that would save.
struct State : MapCore {  // NOLINT(clang-analyzer-optin.performance.Padding)
  CurrentFrame current;      // odometry.cpp (load_frame, the tracking image)
  MotionModel motion;        // odometry.cpp (the pose and its constant-velocity model)
  BrightnessTrack brightness;  // odometry.cpp, tracker and initialiser results
  FrameLoop loop;            // odometry.cpp
  KeyframeSelection selection;  // odometry.cpp (make_keyframe)
  RetiredPoints retired;     // odometry.cpp
  TrackingReference ref;     // tracker.cpp
  InitialiserState init;     // initializer.cpp
  BaSystem ba;               // window_ba.cpp
  MarginalPrior prior;       // window_ba.cpp
  TauEstimator tau_est;      // tau_estimator.cpp
  NoiseEstimate noise;       // noise_estimator.cpp
  ScaleBridge bridge;        // scale_bridge.cpp
};

// The parts make_keyframe() reads and writes besides the map.
inline KeyframeParts keyframe_parts(State& s) { return {s.current, s.motion, s.brightness, s.ref, s.selection}; }

// The factor that takes the scene estimate u = (raw - alpha raw_prev) / beta to the raw level a
// static pixel reads at the frame's timing, beta / (1 - alpha) with the current tau: the tracking
// images then keep the keyframes' level whatever tau is and however t_e and t_r split the frame
// period (exactly 1 when they are equal, tau_h being kept equal to tau_c).
double scene_level_scale(Tau tau, const CurrentFrame& f);
// The current frame's tracking image has the level of keyframe kf's (in the ir modes whatever
// tau is): both settled, at the same timing. The ir modes' images have the raw static level of
// their timing (scene_level_scale), and the raw static levels of two timings differ by a factor
// of the true tau: across a change of timing, and on the frames right after one, the gain and
// offset are estimated (tracker, initialiser; affine's initialiser too).
bool same_level(const CurrentFrame& f, const Keyframe& kf);

// Lays the whole state out over an arena (odometry.cpp); nullptr when it does not fit.
class Arena;
State* lay_out(const VoConfig& config, Arena& arena);

// The ir mode's tracking image: level 0 of f.frame becomes the scene estimate
// (raw - alpha raw_prev) / beta, with f.carry from tau and the frame's times, at the static level
// of the reference timing (times scene_scale = scene_level_scale()); the carry-over correction
// cored against the pixel noise noise_var (VoConfig::carry_coring; odometry.cpp).
void write_scene_estimate(CurrentFrame& f, Tau tau, double noise_var, const VoConfig& cfg);
// After the frame's level 0 is filled: its low-pass, pyramid, gradients and texels (odometry.cpp).
void build_frame_images(CurrentFrame& f, const VoConfig& cfg);

}  // namespace bolo::vo
