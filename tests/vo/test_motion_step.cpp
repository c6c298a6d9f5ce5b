// The constant-velocity guess over frames that were dropped or repeated (motion_step in
// odometry.cpp): the last measured step scaled to the time since the last posed frame.

#include <cmath>
#include <memory>

#include <catch2/catch.hpp>

#include "state.hpp"

using namespace bolo::vo;

namespace {
Vec6 twist() {
  Vec6 xi;
  xi << 0.02, -0.01, 0.15, 0.004, -0.012, 0.002;  // about 0.15 m and 0.7 degrees a frame
  return xi;
}
}  // namespace

TEST_CASE("the motion guess spans the time since the last posed frame", "[vo][motion]") {
  const auto owned = std::make_unique<State>();
  State& s = *owned;
  s.motion.step = Se3::exp(twist());
  s.motion.step_dt_s = 1 / 60.0;
  s.motion.pose_t_s = 1.0;
  SECTION("a regular frame (within timing jitter) gets the step as measured") {
    s.current.t_s = 1.0 + 1.2 / 60.0;
    const Se3 step = motion_step(s.motion, s.current.t_s);
    CHECK(step.t == s.motion.step.t);
    CHECK(step.R == s.motion.step.R);
  }
  SECTION("after one frame dropped or repeated: twice the step") {
    s.current.t_s = 1.0 + 2 / 60.0;
    CHECK((motion_step(s.motion, s.current.t_s).log() - 2 * twist()).norm() < 1e-9);
  }
  SECTION("long gaps are not extrapolated beyond four steps") {
    s.current.t_s = 1.0 + 10 / 60.0;
    CHECK((motion_step(s.motion, s.current.t_s).log() - 4 * twist()).norm() < 1e-9);
  }
  SECTION("no measured interval (start, or times missing): the step as it is") {
    s.motion.step_dt_s = 0;
    s.current.t_s = 1.0 + 3 / 60.0;
    CHECK(motion_step(s.motion, s.current.t_s).t == s.motion.step.t);
  }
}

TEST_CASE("recording a motion stores the interval it spans", "[vo][motion]") {
  const auto owned = std::make_unique<State>();
  State& s = *owned;
  s.motion.pose_t_s = 2.0;
  s.current.t_s = 2.0 + 2 / 60.0;
  const Se3 previous = Se3::exp(twist());
  s.motion.T_cw = Se3::exp(2 * twist()) * previous;
  record_motion(s.motion, previous, s.current.t_s);
  CHECK(s.motion.step_dt_s == Approx(2 / 60.0));
  CHECK(s.motion.pose_t_s == s.current.t_s);
  CHECK((s.motion.step.log() - 2 * twist()).norm() < 1e-9);
  // The next frame, one period later, is guessed one frame's step on.
  s.current.t_s += 1 / 60.0;
  CHECK((motion_step(s.motion, s.current.t_s).log() - twist()).norm() < 1e-9);
}
