// The map's scale across a look-around (VoConfig::scale_bridge).
//
// A monocular map carries its scale from frame to frame only through points seen from both sides
// of a baseline. In a fast turn of the camera (a walker's look-around: ~90 deg in a third of a
// second) the map's points leave the view within a few frames and the points of the new view are
// placed at the window's typical depth (activate_mature_points). The translation tracked in the
// turn is then mostly its rotation error, and after it, with the new view's points at depths that
// are not theirs, the map shrinks at every look-around (the tracking and the depth search shrink
// it, with or without the bundle adjustment).
//
// What does carry over the turn is the camera's velocity: a walker keeps walking and a car keeps
// driving while the camera turns. So the velocity of the last steady stretch of frames (rotating
// slower than kSteadyRotationRate, moving straight) is kept, and at a break of the map (a keyframe
// that has to place points without a baseline while the map had depths) the camera centre is held
// where that velocity carries it: the tracker estimates the rotation and brightness only, until
// the camera has turned no faster than kSteadyRotationRate for kHoldSteadyS and a keyframe has
// been made since. On the turn's fast frames while held, the depth search widens its intervals by
// a share of the rotation (a baseline of centimetres against the turn's rotation error), so the
// new view's points take their depths from the held, steady motion after it, at the old map's
// scale. The window BA stays free. A camera that stands still or does not move steadily before
// the turn has no velocity to carry, and nothing changes; nor does anything on a map that never
// breaks (the drives, the pans).
//
// The hold's release (kHoldSteadyS), its pull and the widened intervals were chosen on 12-s
// handheld walks with look-arounds (scripts/study/long-walks.sh; docs/odometry-study.md, "Long
// walks, look-arounds and restarts").

#include <algorithm>
#include <cmath>

#include "scale_bridge.hpp"

#include "bolo/vo/config.hpp"

namespace bolo::vo {
namespace {

// A frame whose rotation since the frame before is faster than this is part of a turn: its
// tracked translation is not trusted (the turn's rotation error leaks into it).
constexpr double kSteadyRotationRate = 0.8;  // rad/s, ~45 deg/s
// A break holds the centre only after a turn of at least this much since the steady stretch.
constexpr double kMinTurnAngle = 0.5;  // rad, ~30 deg
// The velocity: the steady frames of this long, at least kMinSamples.
constexpr double kVelocityWindowS = 0.6;
constexpr std::uint32_t kMinSamples = 4;
// Steady motion: the displacement over the window is at least this share of the path along it
// (a camera standing still has jitter only, whose path is long against its displacement).
constexpr double kMinStraightness = 0.6;
// Translation flow at the tracked points' mean depth (pixels a second) below which the camera
// counts as standing still: there is no velocity to carry.
constexpr double kMinFlowPixelsPerS = 4.0;
// The hold after a break ends once the camera has moved steadily for this long after the turn
// (and a keyframe was made since); a velocity older than kMaxHoldS is not carried.
constexpr double kHoldSteadyS = 0.8;
constexpr double kMaxHoldS = 2.0;
// While carried, the tracker's prior on the translation, per unit of the translation's own
// information: the camera centre is held (a weaker pull, 10, read 0.94 of the ATE where this
// read 0.65, both released after 0.4 s).
constexpr double kHeldPrior = 1e6;
// On a turn's fast frames a depth match's interval is widened by this share of the frame's
// rotation in pixels: the rotation's error, not the match, limits the depth then.
constexpr double kTurnMarginShare = 0.1;

Vec3 centre(const Se3& T_cw) { return -(T_cw.R.transpose() * T_cw.t); }
void place(Se3& T_cw, const Vec3& c) { T_cw.t = -(T_cw.R * c); }

const MotionSample& sample_back(const ScaleBridge& b, std::uint32_t back) {
  return b.history[(b.head + kMotionHistory - 1 - back) % kMotionHistory];
}

struct Steady {
  Vec3 first = Vec3::Zero(), last = Vec3::Zero();
  double t_first = 0, t_last = 0, path = 0;
  std::uint32_t count = 0;
  double speed() const { return t_last > t_first ? (last - first).norm() / (t_last - t_first) : 0.0; }
  bool straight() const { return path > 0 && (last - first).norm() >= kMinStraightness * path; }
};

// The newest unbroken run of steady samples with t in [from, to] (a turn's frame ends a run): its
// first and last centres and the path between them.
Steady steady_run(const ScaleBridge& b, double from, double to) {
  Steady r;
  for (std::uint32_t back = 0; back < b.count; ++back) {
    const MotionSample& m = sample_back(b, back);
    if (m.t_s > to) continue;
    if (m.t_s < from) break;
    if (m.rotation_rate > kSteadyRotationRate) {
      if (r.count > 0) break;
      continue;
    }
    if (r.count > 0) r.path += (m.centre - r.first).norm();
    if (r.count == 0) r.last = m.centre, r.t_last = m.t_s;
    r.first = m.centre, r.t_first = m.t_s;
    ++r.count;
  }
  return r;
}

bool turning(const ScaleBridge& b) { return b.count > 0 && sample_back(b, 0).rotation_rate > kSteadyRotationRate; }

bool carried(const ScaleBridge& b, double t_s) {
  if (b.carry.suspended || !b.carry.velocity_known || t_s - b.carry.from_t_s > kMaxHoldS) return false;
  return b.carry.after_break;
}

}  // namespace

void record_motion_sample(ScaleBridge& b, const VoConfig& cfg, const Se3& pose, const Se3& previous, double t_s,
                          double dt_s, double ref_mean_idepth) {
  if (!cfg.scale_bridge) return;
  MotionSample& m = b.history[b.head];
  m.t_s = t_s;
  m.centre = centre(pose);
  const Mat3 dR = pose.R * previous.R.transpose();
  const double angle = so3_log(dR).norm();
  m.rotation = static_cast<float>(angle);
  m.rotation_rate = dt_s > 0 ? static_cast<float>(angle / dt_s) : 0.0f;
  b.head = (b.head + 1) % kMotionHistory;
  b.count = std::min(b.count + 1, kMotionHistory);
  // The velocity to carry: the last steady stretch's (not one the bridge itself held).
  if (b.carry.after_break || m.rotation_rate > kSteadyRotationRate) return;
  const Steady run = steady_run(b, t_s - kVelocityWindowS, t_s);
  if (run.count < kMinSamples || !run.straight() || run.t_last - run.t_first < 0.5 * kVelocityWindowS) return;
  if (!(run.speed() * ref_mean_idepth * cfg.camera.fx >= kMinFlowPixelsPerS)) {
    b.carry.velocity_known = false;
    return;
  }
  b.carry.velocity_known = true;
  b.carry.velocity = (run.last - run.first) / (run.t_last - run.t_first);
  b.carry.from_centre = run.last;
  b.carry.from_t_s = run.t_last;
}

Vec3 held_centre(const ScaleBridge& b, double t_s) {
  return b.carry.from_centre + b.carry.velocity * (t_s - b.carry.from_t_s);
}

void note_map_break(ScaleBridge& b, const VoConfig& cfg, bool map_without_baseline, double t_s) {
  if (!cfg.scale_bridge || b.carry.after_break || map_without_baseline) return;
  if (!b.carry.velocity_known || t_s - b.carry.from_t_s > kMaxHoldS) return;
  // A look-around turns the view by a good part of the field of view since the steady stretch; a
  // map that runs out otherwise (a 9 Hz drive's points leave the view in a few frames) is no turn.
  double turned = 0;
  for (std::uint32_t back = 0; back < b.count && sample_back(b, back).t_s > b.carry.from_t_s; ++back)
    turned += sample_back(b, back).rotation;
  if (turned < kMinTurnAngle) return;
  b.carry.after_break = true;
  b.carry.break_s = t_s;
  b.carry.turn_start_s = b.carry.from_t_s;
  b.carry.keyframe_since_turn = false;
}

double translation_prior_weight(const ScaleBridge& b, double t_s, double normal) {
  return carried(b, t_s) ? kHeldPrior : normal;
}

Se3 held_guess(const ScaleBridge& b, double t_s, Se3 guess) {
  if (carried(b, t_s)) place(guess, held_centre(b, t_s));
  return guess;
}

float depth_search_margin(const ScaleBridge& b, const VoConfig& cfg, double t_s) {
  if (!carried(b, t_s) || !turning(b) || b.count < 2) return 0.0f;
  const MotionSample& m = sample_back(b, 0);
  const double dt = m.t_s - sample_back(b, 1).t_s;
  return static_cast<float>(kTurnMarginShare * m.rotation_rate * dt * cfg.camera.fx);
}

bool centre_carried(const ScaleBridge& b, double t_s) { return carried(b, t_s); }

bool update_bridge(ScaleBridge& b, double t_s, bool keyframe_made) {
  if (!b.carry.after_break) return false;
  const bool steady_now = b.count > 0 && !turning(b);
  if (keyframe_made && steady_now) b.carry.keyframe_since_turn = true;
  const Steady after = steady_run(b, b.carry.break_s, t_s);
  const bool settled = steady_now && after.t_last - after.t_first >= kHoldSteadyS && b.carry.keyframe_since_turn;
  if (settled || t_s - b.carry.break_s > kMaxHoldS) {
    b.carry.after_break = false;
    return true;
  }
  return false;
}

}  // namespace bolo::vo
