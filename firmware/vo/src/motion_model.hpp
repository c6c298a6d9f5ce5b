#pragma once
// The camera over frames (odometry.cpp): its pose, the constant-velocity motion model, and the
// frame's affine brightness with what is known about its level.

#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct MotionModel {
  Se3 T_cw;                    // current frame
  Se3 step;                    // last inter-frame motion T_cur_prev, over step_dt_s
  double step_dt_s = 0;        // the time `step` spans (0: unknown)
  double pose_t_s = 0;         // the time of the frame T_cw belongs to
  Se3 last_good;               // last tracked pose (restarts anchor here)
  Se3 T_prev;                  // the previous frame's pose, when prev_posed
  bool prev_posed = false, posed = false;
};

struct BrightnessTrack {
  double a = 0, b = 0;
  bool level_unknown = false;  // a, b are of a frame without its reference's level (same_level)
  bool offset_pending = false;  // ir modes: no frame was posed with a free offset since the chain broke
  double offset_step = 0;  // ir modes: the camera offset's change since the newest keyframe (shutter)
};

// The constant-velocity guess's step from T_cw's frame to the one at `t_s`: `step` scaled to
// the time between them when frames were dropped or repeated in between (odometry.cpp).
Se3 motion_step(const MotionModel& m, double t_s);
// T_cw was just set for the frame at `t_s`, from `previous` (the pose of the frame before): the
// motion model and the time it spans.
void record_motion(MotionModel& m, const Se3& previous, double t_s);

}  // namespace bolo::vo
