#pragma once
// The scale bridge (scale_bridge.cpp, VoConfig::scale_bridge): the camera's velocity carried
// over a look-around.

#include <cstdint>

#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

// A posed frame as the scale bridge remembers it.
struct MotionSample {
  double t_s = 0;
  Vec3 centre = Vec3::Zero();  // camera centre, world
  float rotation_rate = 0;     // rad/s since the frame before
  float rotation = 0;          // rad since the frame before
};
inline constexpr std::uint32_t kMotionHistory = 96;  // 1.6 s at 60 Hz

// The velocity carried over a turn and the carry's progress; a new map starts it afresh.
struct CarriedVelocity {
  bool velocity_known = false;
  Vec3 velocity = Vec3::Zero();     // world, map units a second, of the last steady stretch
  Vec3 from_centre = Vec3::Zero();  // that stretch's last centre, at from_t_s
  double from_t_s = 0;
  bool after_break = false;          // the map broke in a turn: carried until the camera is steady
  double turn_start_s = 0, break_s = 0;
  bool keyframe_since_turn = false;  // a keyframe was made on a steady frame since the break
  bool suspended = false;            // a frame tracked free while held (odometry.cpp)
};

struct ScaleBridge {
  MotionSample history[kMotionHistory];  // the last posed frames, newest at head - 1
  std::uint32_t head = 0, count = 0;
  CarriedVelocity carry;
};

// Each tracked frame's centre and rotation rate, from the pose of the frame before (`dt_s`
// earlier), and the velocity of the last steady stretch; a break of the map (called where a
// keyframe places points without a baseline on a map that had depths); while the velocity is
// carried (a fast turn, and after a break until the camera is steady), the tracker's prior weight
// on the translation and a guess with the carried centre (else `normal` and the guess itself);
// whether the velocity is carried; the depth search's extra margin on the current frame (pixels:
// on a fast turn's frames, a share of the rotation since the frame before); and, after each
// tracked frame, the end of a break's carry (returns true when it ended).
void record_motion_sample(ScaleBridge& b, const VoConfig& cfg, const Se3& pose, const Se3& previous, double t_s,
                          double dt_s, double ref_mean_idepth);
void note_map_break(ScaleBridge& b, const VoConfig& cfg, bool map_without_baseline, double t_s);
double translation_prior_weight(const ScaleBridge& b, double t_s, double normal);
Se3 held_guess(const ScaleBridge& b, double t_s, Se3 guess);
bool centre_carried(const ScaleBridge& b, double t_s);
float depth_search_margin(const ScaleBridge& b, const VoConfig& cfg, double t_s);
bool update_bridge(ScaleBridge& b, double t_s, bool keyframe_made);

}  // namespace bolo::vo
