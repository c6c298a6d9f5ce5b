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
  s.motion = Se3::exp(twist());
  s.motion_dt_s = 1 / 60.0;
  s.pose_t_s = 1.0;
  SECTION("a regular frame (within timing jitter) gets the step as measured") {
    s.t_s = 1.0 + 1.2 / 60.0;
    const Se3 step = motion_step(s);
    CHECK(step.t == s.motion.t);
    CHECK(step.R == s.motion.R);
  }
  SECTION("after one frame dropped or repeated: twice the step") {
    s.t_s = 1.0 + 2 / 60.0;
    CHECK((motion_step(s).log() - 2 * twist()).norm() < 1e-9);
  }
  SECTION("long gaps are not extrapolated beyond four steps") {
    s.t_s = 1.0 + 10 / 60.0;
    CHECK((motion_step(s).log() - 4 * twist()).norm() < 1e-9);
  }
  SECTION("no measured interval (start, or times missing): the step as it is") {
    s.motion_dt_s = 0;
    s.t_s = 1.0 + 3 / 60.0;
    CHECK(motion_step(s).t == s.motion.t);
  }
}

TEST_CASE("recording a motion stores the interval it spans", "[vo][motion]") {
  const auto owned = std::make_unique<State>();
  State& s = *owned;
  s.pose_t_s = 2.0;
  s.t_s = 2.0 + 2 / 60.0;
  const Se3 previous = Se3::exp(twist());
  s.T_cw = Se3::exp(2 * twist()) * previous;
  record_motion(s, previous);
  CHECK(s.motion_dt_s == Approx(2 / 60.0));
  CHECK(s.pose_t_s == s.t_s);
  CHECK((s.motion.log() - 2 * twist()).norm() < 1e-9);
  // The next frame, one period later, is guessed one frame's step on.
  s.t_s += 1 / 60.0;
  CHECK((motion_step(s).log() - twist()).norm() < 1e-9);
}
