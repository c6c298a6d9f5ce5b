// The monocular initialiser under a rotation about the camera's centre: the street pan (30 deg/s),
// rendered without ghosting, with pixel noise. Across a 50-degree field of view a turn moves the
// image almost as a sideways step at the mean depth does, and the joint pose-and-depth solve took
// it for one. At 9 Hz the initialisation then waited ~2 s for its fresh and warm solves to agree
// on the step's direction, by when the first keyframe had turned out of the view, and the map it
// made held a translation that was never there. The initialiser now also fits a rotation alone
// and takes it when it explains the frame about as well (explained_by_rotation, initializer.cpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/odometry.hpp"
#include "rendered_pair.hpp"

using namespace bolo;

namespace {

double rotation_angle_deg(const vo::Mat3& R) { return vo::so3_log(R).norm() * 180.0 / M_PI; }

struct PanRun {
  int first_posed = -1;
  double translation_at_first = 0;      // |t| of the first pose, in mean depths
  double rotation_error_at_first = 0;   // degrees, against the true turn since the start
  int posed = 0;
  int tracked_to = -1;                  // the last frame of the first map's unbroken run of poses
  double worst_rotation_error = 0;      // degrees, over that run
};

PanRun run_pan(double fps, int frames, vo::Photometric mode) {
  const test::RenderedSequence seq{"street", "pan", 160, 120, 3, 2};
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height;
  cfg.camera = seq.intrinsics();
  cfg.photometric = mode;
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Odometry odometry(cfg, memory);
  REQUIRE(odometry.ok());
  PanRun run;
  const vo::Se3 start_from_world = seq.T_cw(0.0);
  std::uint64_t noise = 88172645463325252ull;
  for (int i = 0; i < frames; ++i) {
    std::vector<std::uint16_t> frame = seq.frame(i / fps);
    // Pixel noise (uniform, +-5 counts: 2.9 rms), from a fixed xorshift. On the noise-free render
    // the map starved at frame 14 instead (the depth search's weakness on noise-free frames,
    // docs/odometry-study.md).
    for (auto& v : frame) {
      noise ^= noise << 13, noise ^= noise >> 7, noise ^= noise << 17;
      v = static_cast<std::uint16_t>(v + static_cast<int>(noise % 11) - 5);
    }
    vo::FrameInput in;
    in.raw = frame;
    in.t_s = i / fps;
    in.chain_broken = i == 0;
    const vo::FrameResult r = odometry.process(in);
    if (!r.has_pose) continue;
    // The VO's world is the first keyframe's camera, which is the start's.
    const vo::Mat3 true_turn = seq.T_cw(in.t_s).R * start_from_world.R.transpose();
    const vo::Mat3 estimated_turn = r.T_wc.R.transpose();
    const double error = rotation_angle_deg(estimated_turn * true_turn.transpose());
    if (run.first_posed < 0) {
      run.first_posed = i;
      run.translation_at_first = r.T_wc.t.norm();
      run.rotation_error_at_first = error;
    }
    ++run.posed;
    if (run.tracked_to == i - 1 || run.tracked_to < 0) {
      run.tracked_to = i;
      run.worst_rotation_error = std::max(run.worst_rotation_error, error);
    }
  }
  return run;
}

}  // namespace

TEST_CASE("the initialiser takes a pan for the rotation it is", "[vo][init][long]") {
  // 3.3 s of the pan, 100 degrees over the street before it faces a blank wall. Measured when
  // written (both modes): the first pose at frames 3 / 5 / 10 (9 / 15 / 30 Hz) with no
  // translation, 0.010-0.013 degrees off the true turn; then every frame tracked to the end, at
  // most 0.12-0.21 degrees off. The joint solve alone took the pan for a sideways step: its first
  // pose came at frame 18 / 38 / 30 with a translation of 0.6 / 0.4 / 0.1 mean depths and the turn
  // 61 / 77 / 7 degrees off. With the map begun as a rotation but the rotation's points activated
  // only below 50 tracked points, the 9 Hz map starved at frame 14 (10 px of turn a frame take
  // 30-40 tracked points out of the view each frame).
  for (const double fps : {9.0, 15.0, 30.0}) {
    const int frames = static_cast<int>(3.3 * fps);
    for (const vo::Photometric mode : {vo::Photometric::none, vo::Photometric::affine}) {
      const PanRun run = run_pan(fps, frames, mode);
      INFO(fps << " Hz, mode " << static_cast<int>(mode) << ": first posed " << run.first_posed << ", |t| "
               << run.translation_at_first << ", rotation error " << run.rotation_error_at_first << " deg; tracked to "
               << run.tracked_to << ", posed " << run.posed << " of " << frames << ", worst " << run.worst_rotation_error
               << " deg");
      REQUIRE(run.first_posed >= 0);
      CHECK(run.first_posed <= static_cast<int>(fps / 3.0) + 1);
      CHECK(run.translation_at_first < 1e-6);
      CHECK(run.rotation_error_at_first < 0.5);
      CHECK(run.worst_rotation_error < 1.0);
      CHECK(run.tracked_to == frames - 1);
    }
  }
}
