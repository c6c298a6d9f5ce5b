// The scale bridge's bookkeeping (scale_bridge.cpp) on poses fed by hand: which velocity it keeps,
// when a break of the map holds the camera centre on it, what the tracker and the depth search are
// told meanwhile, and when the hold ends.

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/arena.hpp"
#include "state.hpp"

using namespace bolo;

namespace {

struct Bridged {
  std::vector<std::byte> memory;
  vo::State* s = nullptr;
  vo::Se3 pose;  // world to camera of the last frame fed

  explicit Bridged(bool scale_bridge = true) {
    vo::VoConfig cfg;
    cfg.width = 160, cfg.height = 120;
    cfg.camera = {170.0f, 170.0f, 79.5f, 59.5f};
    cfg.scale_bridge = scale_bridge;
    memory.resize(vo::Odometry::arena_bytes(cfg));
    vo::Arena arena(memory);
    s = vo::lay_out(cfg, arena);
    REQUIRE(s != nullptr);
    s->ref.mean_idepth = 1.0;  // the tracked points 1 map unit away
  }

  // A tracked frame at t with its camera centre and a yaw (rad) about the camera's y axis.
  void feed(double t, const vo::Vec3& centre, double yaw) {
    const vo::Se3 previous = pose;
    pose.R = vo::so3_exp(vo::Vec3(0, yaw, 0));
    pose.t = -(pose.R * centre);
    const double dt = t - s->current.t_s;
    s->current.t_s = t;
    s->motion.T_cw = pose;
    vo::record_motion_sample(s->bridge, s->cfg, s->motion.T_cw, previous, s->current.t_s, dt, s->ref.mean_idepth);
  }
  vo::Vec3 held_centre() const {
    const vo::Se3 g = vo::held_guess(s->bridge, s->current.t_s, pose);
    return -(g.R.transpose() * g.t);
  }
};

constexpr double kDt = 1.0 / 60.0;

// 1 s walking along x at 0.1 map units a second, then a turn of 90 deg in 0.25 s: frame times
// k * kDt for k < frames.
void walk_then_turn(Bridged& b, int frames) {
  for (int k = 0; k < frames; ++k) {
    const double t = k * kDt;
    const double turn = std::clamp((t - 1.0) / 0.25, 0.0, 1.0) * M_PI / 2;
    b.feed(t, vo::Vec3(0.1 * t, 0.003 * std::sin(12 * t), 0), turn);
  }
}

}  // namespace

TEST_CASE("scale bridge: a break in a turn holds the centre on the velocity before it", "[vo][bridge]") {
  Bridged b;
  walk_then_turn(b, 72);  // into the turn (t = 1.18 s)
  REQUIRE(b.s->bridge.carry.velocity_known);
  CHECK(b.s->bridge.carry.velocity.x() == Approx(0.1).epsilon(0.05));
  CHECK(std::fabs(b.s->bridge.carry.velocity.y()) < 0.01);
  CHECK(b.s->bridge.carry.from_t_s < 1.0 + kDt);  // the turn's frames do not move it
  CHECK_FALSE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
  CHECK(vo::translation_prior_weight(b.s->bridge, b.s->current.t_s, 0.02) == 0.02);

  vo::note_map_break(b.s->bridge, b.s->cfg, b.s->init.map_without_baseline, b.s->current.t_s);
  REQUIRE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
  CHECK(vo::translation_prior_weight(b.s->bridge, b.s->current.t_s, 0.02) > 1e3);
  // The guess keeps its rotation and gets the carried centre.
  const vo::Vec3 expected = b.s->bridge.carry.from_centre + b.s->bridge.carry.velocity * (b.s->current.t_s - b.s->bridge.carry.from_t_s);
  CHECK((b.held_centre() - expected).norm() < 1e-12);
  CHECK((vo::held_guess(b.s->bridge, b.s->current.t_s, b.pose).R - b.pose.R).norm() < 1e-12);
  // On the turn's fast frames the depth search widens its intervals by a share of the rotation.
  const float margin = vo::depth_search_margin(b.s->bridge, b.s->cfg, b.s->current.t_s);
  const double per_frame_px = (M_PI / 2 / 0.25) * kDt * 170.0;
  CHECK(margin == Approx(0.1 * per_frame_px).epsilon(0.05));
}

TEST_CASE("scale bridge: the hold ends once the camera is steady and a keyframe was made", "[vo][bridge]") {
  Bridged b;
  walk_then_turn(b, 72);
  vo::note_map_break(b.s->bridge, b.s->cfg, b.s->init.map_without_baseline, b.s->current.t_s);
  REQUIRE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
  // The rest of the turn and 0.8 s of steady frames after it (t 1.25 .. 2.05 s), no keyframe.
  int k = 72;
  for (; k * kDt < 2.1; ++k) {
    b.feed(k * kDt, vo::Vec3(0.1 * k * kDt, 0, 0), M_PI / 2);
    CHECK_FALSE(vo::update_bridge(b.s->bridge, b.s->current.t_s, false));
  }
  CHECK(vo::depth_search_margin(b.s->bridge, b.s->cfg, b.s->current.t_s) == 0.0f);  // steady now
  // A keyframe on a steady frame: released at the next steady frame that has 0.8 s behind it.
  b.feed(k * kDt, vo::Vec3(0.1 * k * kDt, 0, 0), M_PI / 2);
  CHECK(vo::update_bridge(b.s->bridge, b.s->current.t_s, true));
  CHECK_FALSE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
}

TEST_CASE("scale bridge: without a keyframe the hold ends after 2 s", "[vo][bridge]") {
  Bridged b;
  walk_then_turn(b, 72);
  vo::note_map_break(b.s->bridge, b.s->cfg, b.s->init.map_without_baseline, b.s->current.t_s);
  const double break_s = b.s->current.t_s;
  int k = 72;
  bool ended = false;
  for (; !ended && k < 400; ++k) {
    b.feed(k * kDt, vo::Vec3(0.1 * k * kDt, 0, 0), M_PI / 2);
    ended = vo::update_bridge(b.s->bridge, b.s->current.t_s, false);
  }
  CHECK(ended);
  CHECK(b.s->current.t_s - break_s == Approx(2.0).margin(2 * kDt));
}

TEST_CASE("scale bridge: a camera standing still has no velocity to carry", "[vo][bridge]") {
  Bridged b;
  // Jitter of a millimetre around the origin, then the turn.
  for (int k = 0; k < 72; ++k) {
    const double t = k * kDt;
    const double turn = std::clamp((t - 1.0) / 0.25, 0.0, 1.0) * M_PI / 2;
    b.feed(t, vo::Vec3(0.001 * std::sin(40 * t), 0.001 * std::cos(33 * t), 0), turn);
  }
  CHECK_FALSE(b.s->bridge.carry.velocity_known);
  vo::note_map_break(b.s->bridge, b.s->cfg, b.s->init.map_without_baseline, b.s->current.t_s);
  CHECK_FALSE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
  CHECK(vo::held_guess(b.s->bridge, b.s->current.t_s, b.pose).t == b.pose.t);
}

TEST_CASE("scale bridge: off in the configuration, nothing is recorded or held", "[vo][bridge]") {
  Bridged b(false);
  walk_then_turn(b, 72);
  CHECK(b.s->bridge.count == 0);
  vo::note_map_break(b.s->bridge, b.s->cfg, b.s->init.map_without_baseline, b.s->current.t_s);
  CHECK_FALSE(vo::centre_carried(b.s->bridge, b.s->current.t_s));
  CHECK(vo::depth_search_margin(b.s->bridge, b.s->cfg, b.s->current.t_s) == 0.0f);
}
