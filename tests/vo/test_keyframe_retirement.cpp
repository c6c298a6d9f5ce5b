// Which keyframe leaves a full window (keyframe_retirement.cpp) and how the window closes the gap
// (new_keyframe_slot in odometry.cpp).

#include <array>
#include <memory>
#include <vector>

#include <catch2/catch.hpp>

#include "state.hpp"

using namespace bolo::vo;

namespace {

constexpr std::uint32_t kPointsEach = 10;

// A window of keyframes whose camera centres lie at `centres` along the optical axis (oldest
// first), each turned by `yaw_deg[k]` about the vertical, and each hosting kPointsEach active
// points 5 m away.
struct Window {
  std::unique_ptr<State> owned = std::make_unique<State>();
  std::vector<std::array<Point, kPointsEach>> points;
  std::vector<float> scratch = std::vector<float>(kMaxKeyframes * kPointsEach);
  std::vector<WorldPoint> retired = std::vector<WorldPoint>(kMaxKeyframes * kPointsEach);
  std::vector<std::vector<float>> images;  // the keyframes' pyramids (a retired point takes its intensity)

  Window(const std::vector<double>& centres, const std::vector<double>& yaw_deg, Retirement retirement) {
    State& s = *owned;
    s.cfg.width = 160, s.cfg.height = 120;
    s.cfg.camera = {140.0f, 140.0f, 79.5f, 59.5f};
    s.cfg.max_keyframes = kMaxKeyframes;
    s.cfg.retirement = retirement;
    s.scratch = scratch;
    s.retired.points = retired;
    points.resize(centres.size());
    images.resize(centres.size(), std::vector<float>(pyramid_floats(160, 120, 1)));
    for (std::uint32_t k = 0; k < centres.size(); ++k) {
      Keyframe& kf = s.kf[k];
      kf.used = true;
      kf.pyramid = make_pyramid(images[k], 160, 120, 1);
      kf.id = k;
      const Mat3 R = so3_exp(Vec3(0, yaw_deg[k] * 3.14159265358979 / 180.0, 0));
      kf.T_cw = {R, -(R * Vec3(0, 0, centres[k]))};
      for (std::uint32_t i = 0; i < kPointsEach; ++i) {
        Point& p = points[k][i];
        p.u = 20.0f + 12.0f * static_cast<float>(i), p.v = 60.0f, p.idepth = 0.2f;
        p.status = PointStatus::active;
      }
      kf.points = points[k];
      kf.count = kPointsEach;
      s.order[k] = k;
    }
    s.kf_count = static_cast<std::uint32_t>(centres.size());
  }
  State& state() { return *owned; }
};

const std::vector<double> kStraight(kMaxKeyframes, 0.0);

}  // namespace

TEST_CASE("a full window retires the oldest keyframe while the keyframes are evenly spread", "[vo][retirement]") {
  Window w({0.0, 0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 2.1}, kStraight, Retirement::spread);
  CHECK(keyframe_to_retire(w.state()) == 0);
}

TEST_CASE("a keyframe made for a turn leaves before the oldest, which holds the baseline", "[vo][retirement]") {
  // Keyframes 3 and 4 were made 1 cm apart while the camera turned; the window's mean spacing
  // is 0.26 m.
  Window w({0.0, 0.3, 0.6, 0.9, 0.91, 1.2, 1.5, 1.8}, {0, 0, 0, 0, 30, 30, 30, 30}, Retirement::spread);
  State& s = w.state();
  const std::uint32_t leaving = keyframe_to_retire(s);
  CHECK((leaving == 3 || leaving == 4));

  SECTION("the window closes the gap and keeps its order, the oldest still first") {
    const std::uint32_t gone = s.order[leaving];
    const std::uint32_t slot = new_keyframe_slot(s, s.retired, s.ba, s.prior);
    CHECK(slot == gone);
    CHECK(s.kf_count == kMaxKeyframes - 1);
    CHECK(s.order[0] == 0);
    for (std::uint32_t k = 1; k < s.kf_count; ++k) CHECK(s.kf[s.order[k]].id > s.kf[s.order[k - 1]].id);
    CHECK(s.retired.count == kPointsEach);  // the leaving keyframe's points are map output
  }
  SECTION("with --retirement oldest, or with the marginalisation prior (built from the oldest), the oldest leaves") {
    s.cfg.retirement = Retirement::oldest;
    CHECK(keyframe_to_retire(s) == 0);
    s.cfg.retirement = Retirement::spread;
    s.cfg.marginalisation_prior = true;
    CHECK(keyframe_to_retire(s) == 0);
  }
  SECTION("without the window BA no prior is built, so the prior's flag alone does not hold the oldest") {
    s.cfg.marginalisation_prior = true;
    s.cfg.window_ba = false;
    CHECK(keyframe_to_retire(s) == leaving);
  }
}

TEST_CASE("the two newest keyframes never leave, however near each other", "[vo][retirement]") {
  Window w({0.0, 0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 1.81}, kStraight, Retirement::spread);
  CHECK(keyframe_to_retire(w.state()) == 0);
}

TEST_CASE("a window without a baseline (a pan) retires the oldest", "[vo][retirement]") {
  // The centres drift by 2 mm a keyframe while the view turns 10 degrees a keyframe; keyframes
  // 3 and 4 are 0.1 mm apart, crowded against that drift, but the whole window's baseline is a
  // third of a pixel at the points' depth: there is none to keep.
  Window w({0.0, 0.002, 0.004, 0.006, 0.0061, 0.008, 0.010, 0.012}, {0, 10, 20, 30, 40, 50, 60, 70}, Retirement::spread);
  CHECK(keyframe_to_retire(w.state()) == 0);
}
