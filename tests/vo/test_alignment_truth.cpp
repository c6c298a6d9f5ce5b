// The VO's numerical parts against rendered ground truth: direct alignment recovers the true
// relative pose when the depths are true, and the epipolar search recovers true depths when the
// pose is true. Frames are rendered in-process (no noise), 160x120, street scene, drive.

#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/arena.hpp"
#include "rendered_pair.hpp"
#include "state.hpp"

using namespace bolo;

namespace {

struct Fixture {
  test::RenderedSequence seq{"street", "drive", 160, 120};
  vo::VoConfig cfg;
  std::vector<std::byte> memory;
  vo::State* s = nullptr;

  explicit Fixture(vo::Photometric mode = vo::Photometric::none) {
    cfg.width = seq.width, cfg.height = seq.height;
    cfg.camera = seq.intrinsics();
    cfg.photometric = mode;
    memory.resize(vo::Odometry::arena_bytes(cfg));
    vo::Arena arena(memory);
    s = vo::lay_out(cfg, arena);
    REQUIRE(s != nullptr);
  }
  void load(double t) {
    const auto f = seq.frame(t);
    for (std::size_t i = 0; i < f.size(); ++i) s->frame.level[0].value.data[i] = f[i], s->raw[i] = f[i];
    vo::build_frame_images(*s);
    s->t_s = t;
  }
  // A keyframe at time t with points at their true depth (active) or unknown (immature).
  vo::Keyframe& keyframe(double t, bool true_depth) {
    load(t);
    s->T_cw = seq.T_cw(t);
    const std::uint32_t slot = vo::new_keyframe_slot(*s);
    vo::make_keyframe(*s, slot, true);
    vo::Keyframe& kf = s->kf[slot];
    for (std::uint32_t i = 0; i < kf.count; ++i) {
      vo::Point& p = kf.points[i];
      const double z = seq.depth(t, p.u, p.v);
      if (z <= 0 || z > 150) {
        p.status = vo::PointStatus::empty;
        continue;
      }
      p.idepth = static_cast<float>(1.0 / z);
      if (true_depth) p.status = vo::PointStatus::active;
    }
    return kf;
  }
};

double angle_deg(const vo::Mat3& R) { return vo::so3_log(R).norm() * 180.0 / M_PI; }

}  // namespace

TEST_CASE("direct alignment recovers the true motion from true depths", "[vo][tracker]") {
  Fixture f;
  const double t0 = 2.0, t1 = 2.0 + 4.0 / 60.0;
  f.keyframe(t0, true);
  f.load(t1);
  const vo::Se3 truth = f.seq.T_cw(t1);
  const vo::TrackResult r = vo::track_frame(*f.s, f.seq.T_cw(t0), 0, 0, false);
  const vo::Se3 error = truth * r.T_cw.inverse();
  const vo::Se3 motion = truth * f.seq.T_cw(t0).inverse();
  const vo::Se3 estimated = r.T_cw * f.seq.T_cw(t0).inverse();
  INFO("estimated translation " << estimated.t.transpose() << " true " << motion.t.transpose());
  INFO("rms " << r.rms << " inliers " << r.inliers << "/" << r.visible << " translation error " << error.t.norm()
              << " m of " << motion.t.norm() << " m, rotation error " << angle_deg(error.R) << " deg");
  const vo::TrackResult from_truth = vo::track_frame(*f.s, truth, 0, 0, false);
  INFO("started at the truth: ends " << (truth * from_truth.T_cw.inverse()).t.norm() << " m away, rms " << from_truth.rms);
  CHECK(r.ok);
  CHECK(error.t.norm() < 0.1 * motion.t.norm());
  CHECK(angle_deg(error.R) < 0.2);
}

TEST_CASE("epipolar search recovers true inverse depths from the true pose", "[vo][depth]") {
  Fixture f;
  const double t0 = 2.0;
  vo::Keyframe& kf = f.keyframe(t0, false);
  std::vector<float> truth(kf.count);
  for (std::uint32_t i = 0; i < kf.count; ++i) truth[i] = kf.points[i].idepth, kf.points[i].idepth = 1;
  for (int k = 1; k <= 6; ++k) {
    const double t = t0 + k / 60.0;
    f.load(t);
    f.s->T_cw = f.seq.T_cw(t);
    vo::search_immature_points(*f.s);
  }
  vo::activate_mature_points(*f.s);
  std::vector<double> rel;
  std::uint32_t active = 0;
  for (std::uint32_t i = 0; i < kf.count; ++i) {
    const vo::Point& p = kf.points[i];
    if (p.status != vo::PointStatus::active) continue;
    ++active;
    rel.push_back(std::fabs(p.idepth - truth[i]) / truth[i]);
  }
  REQUIRE(active > 20);
  std::sort(rel.begin(), rel.end());
  INFO(active << " of " << kf.count << " activated; median relative error " << rel[rel.size() / 2]
              << ", 80th percentile " << rel[rel.size() * 8 / 10]);
  CHECK(rel[rel.size() / 2] < 0.1);
  CHECK(rel[rel.size() * 8 / 10] < 0.3);
}

TEST_CASE("window bundle adjustment pulls a perturbed keyframe back to the truth", "[vo][ba]") {
  Fixture f;
  const double times[] = {2.0, 2.0 + 3.0 / 60.0, 2.0 + 6.0 / 60.0, 2.0 + 9.0 / 60.0};
  for (double t : times) f.keyframe(t, true);
  // Perturb the newest keyframe by 10 cm and 0.3 degrees, and all inverse depths by 5 %.
  vo::Keyframe& newest = f.s->kf[f.s->order[f.s->kf_count - 1]];
  vo::Vec6 xi;
  xi << 0.06, -0.05, 0.06, 0.003, -0.003, 0.002;
  newest.T_cw = vo::Se3::exp(xi) * newest.T_cw;
  for (auto& kf : f.s->kf)
    for (std::uint32_t i = 0; i < kf.count; ++i) kf.points[i].idepth *= (i % 2 ? 1.05f : 0.95f);
  const double before = (newest.T_cw * f.seq.T_cw(times[3]).inverse()).t.norm();
  vo::window_bundle_adjustment(*f.s);
  const vo::Se3 error = newest.T_cw * f.seq.T_cw(times[3]).inverse();
  INFO("newest keyframe error " << before << " m before, " << error.t.norm() << " m after, rotation "
                                << angle_deg(error.R) << " deg");
  CHECK(error.t.norm() < 0.3 * before);
  CHECK(angle_deg(error.R) < 0.15);
}
