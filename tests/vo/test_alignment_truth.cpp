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
    // The components on the rendered frames as they are: these noise-free one-ray frames are what
    // the bounds were measured on. With the default low-pass (VoConfig::smoothing 1) the depth
    // search activated 41 of 480 points at a median error of 19 % (unambiguous-looking matches in
    // weak texture), and the BA left 0.031 m and 0.16 deg; the whole VO on such frames does better
    // with it (docs/odometry-study.md, "Accuracy").
    cfg.smoothing = 0;
    memory.resize(vo::Odometry::arena_bytes(cfg));
    vo::Arena arena(memory);
    s = vo::lay_out(cfg, arena);
    REQUIRE(s != nullptr);
  }
  // `blur`: box-blur passes (3x3) before the pyramid is built; then the image is made
  // e^a * image + b (the affine brightness model's frame with parameters a, b).
  void load(double t, int blur = 0, double a = 0, double b = 0) {
    const auto counts = seq.frame(t);
    std::vector<float> f(counts.begin(), counts.end());
    const std::size_t w = seq.width, h = seq.height;
    for (int pass = 0; pass < blur; ++pass) {
      auto g = f;
      for (std::size_t y = 1; y + 1 < h; ++y)
        for (std::size_t x = 1; x + 1 < w; ++x) {
          float sum = 0;
          for (std::size_t dy = 0; dy < 3; ++dy)
            for (std::size_t dx = 0; dx < 3; ++dx) sum += f[(y + dy - 1) * w + x + dx - 1];
          g[y * w + x] = sum / 9.0f;
        }
      f = g;
    }
    for (float& v : f) v = static_cast<float>(std::exp(a) * v + b);
    for (std::size_t i = 0; i < f.size(); ++i) s->current.frame.level[0].value.data[i] = f[i], s->current.raw[i] = f[i];
    vo::build_frame_images(s->current, s->cfg);
    s->current.t_s = t;
  }
  // A keyframe at time t with points at their true depth (active) or unknown (immature).
  vo::Keyframe& keyframe(double t, bool true_depth, int blur = 0, double a = 0, double b = 0) {
    load(t, blur, a, b);
    s->brightness.a = a, s->brightness.b = b;
    s->motion.T_cw = seq.T_cw(t);
    const std::uint32_t slot = vo::new_keyframe_slot(*s, s->retired, s->ba, s->prior);
    vo::make_keyframe(*s, vo::keyframe_parts(*s), slot, true);
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
  const vo::TrackResult r = vo::track_frame(f.s->ref, *f.s, f.s->current, f.s->bridge, f.seq.T_cw(t0), 0, 0, {});
  const vo::Se3 error = truth * r.T_cw.inverse();
  const vo::Se3 motion = truth * f.seq.T_cw(t0).inverse();
  const vo::Se3 estimated = r.T_cw * f.seq.T_cw(t0).inverse();
  INFO("estimated translation " << estimated.t.transpose() << " true " << motion.t.transpose());
  INFO("rms " << r.rms << " inliers " << r.inliers << "/" << r.visible << " translation error " << error.t.norm()
              << " m of " << motion.t.norm() << " m, rotation error " << angle_deg(error.R) << " deg");
  const vo::TrackResult from_truth = vo::track_frame(f.s->ref, *f.s, f.s->current, f.s->bridge, truth, 0, 0, {});
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
    f.s->motion.T_cw = f.seq.T_cw(t);
    vo::search_immature_points(*f.s, f.s->current, f.s->motion, f.s->brightness);
  }
  vo::activate_mature_points(*f.s, f.s->ref, f.s->bridge, f.s->init, f.s->current.t_s, /*tracked_points=*/1000);  // a well-tracked frame
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
  vo::window_bundle_adjustment(*f.s, f.s->ba, f.s->prior, f.s->ref);
  const vo::Se3 error = newest.T_cw * f.seq.T_cw(times[3]).inverse();
  INFO("newest keyframe error " << before << " m before, " << error.t.norm() << " m after, rotation "
                                << angle_deg(error.R) << " deg");
  CHECK(error.t.norm() < 0.3 * before);
  CHECK(angle_deg(error.R) < 0.15);
}

// The window BA's system against finite differences of its energy. With Huber and gradient
// weights out of the way (all weights 1) the energy is E = sum r^2 and the system holds
// b = J^T r = dE/dx / 2 and H = J^T J, whose columns are (near the truth, residuals small) the
// derivatives of b. The images are blurred so that their central-difference gradients, which
// the Jacobians use, are the slopes of the bilinear interpolation the energy sees. Host and target parameters both enter every observation, so this checks the
// host Jacobians the BA maps from the target's as well as its own.
TEST_CASE("window bundle adjustment's system matches finite differences of its energy", "[vo][ba]") {
  Fixture f;
  f.s->cfg.huber_counts = 1e7f;
  f.s->cfg.gradient_c = 1e7f;
  // A wide baseline and brightness far apart, so that the terms of the host Jacobians that depend
  // on the relative translation and gain are not lost in the finite differences' tolerance.
  const double times[] = {2.0, 2.0 + 12.0 / 60.0, 2.0 + 24.0 / 60.0};
  // Each keyframe with its own brightness (and images to match), so the affine terms' host and
  // target derivatives differ while the residuals stay small.
  for (int k = 0; k < 3; ++k) f.keyframe(times[k], true, 25, 0.25 * k, 20.0 * k);
  vo::State& s = *f.s;
  vo::window_system(s, s.ba);
  const vo::BaVector b = s.ba.b;
  // Parameter q of keyframe `place` moved by `step`.
  const auto nudge = [&s](std::uint32_t place, int q, double step) {
    vo::Keyframe& kf = s.kf[s.order[place]];
    if (q < 6) {
      vo::Vec6 d = vo::Vec6::Zero();
      d[q] = step;
      kf.T_cw = vo::Se3::exp(d) * kf.T_cw;
    } else if (q == 6) {
      kf.a += step;
    } else {
      kf.b += step;
    }
  };
  const double steps[8] = {1e-4, 1e-4, 1e-4, 1e-5, 1e-5, 1e-5, 1e-4, 1e-2};
  int b_checked = 0;
  for (std::uint32_t place = 0; place < s.kf_count; ++place) {
    for (int q = 0; q < 8; ++q) {
      const int index = static_cast<int>(8 * place) + q;
      const vo::Keyframe saved = s.kf[s.order[place]];
      nudge(place, q, steps[q]);
      const double e_plus = vo::window_system(s, s.ba);
      s.kf[s.order[place]] = saved;
      nudge(place, q, -steps[q]);
      const double e_minus = vo::window_system(s, s.ba);
      s.kf[s.order[place]] = saved;
      const double gradient = (e_plus - e_minus) / (4 * steps[q]);  // dE/dx / 2
      INFO("keyframe " << place << " parameter " << q << ": b " << b[index] << ", finite difference " << gradient);
      // Finite differences of a piecewise-bilinear energy are not exact: 10 %, and 5 % of the
      // largest component of the same kind (pose axis, a or b) over the keyframes.
      double kind_scale = 0;
      for (std::uint32_t k = 0; k < s.kf_count; ++k) kind_scale = std::max(kind_scale, std::fabs(b[8 * k + q]));
      CHECK(std::fabs(b[index] - gradient) <= 0.1 * std::fabs(gradient) + 0.05 * kind_scale);
      ++b_checked;
    }
  }
  CHECK(b_checked == 24);
}

// A retired keyframe's information stays as a prior on the rest of the window. A monocular
// window's scale is free, so the prior must hold the window's shape without holding its scale:
// a quadratic prior read naively pulls the scale towards 0 (the drive's scale shrank 20 % in
// 3 s before it was read in its linearisation's scale).
TEST_CASE("the marginalisation prior holds the window's shape but not its scale", "[vo][ba]") {
  Fixture f;
  vo::State& s = *f.s;
  s.cfg.max_keyframes = 4;
  s.cfg.marginalisation_prior = true;
  for (int k = 0; k < 4; ++k) f.keyframe(2.0 + 0.2 * k, true);
  REQUIRE(s.kf_count == 4);
  CHECK_FALSE(s.prior.set);
  CHECK(vo::marginal_prior_energy(s, s.prior) == 0.0);
  f.keyframe(2.8, true);  // the oldest retires: its points and then its pose are eliminated
  REQUIRE(s.prior.set);
  CHECK(s.kf_count == 4);
  // At its linearisation point the prior costs nothing (up to rounding).
  const double at_linearisation = vo::marginal_prior_energy(s, s.prior);
  vo::Keyframe saved[vo::kMaxKeyframes];
  for (std::uint32_t k = 0; k < vo::kMaxKeyframes; ++k) saved[k] = s.kf[k];
  const auto restore = [&] {
    for (std::uint32_t k = 0; k < vo::kMaxKeyframes; ++k) s.kf[k] = saved[k];
  };
  const auto centre = [](const vo::Se3& T) -> vo::Vec3 { return -(T.R.transpose() * T.t); };
  // The window 25 % larger about its oldest keyframe: no cost.
  const vo::Vec3 c0 = centre(s.kf[s.order[0]].T_cw);
  for (std::uint32_t k = 1; k < s.kf_count; ++k) {
    vo::Se3& T = s.kf[s.order[k]].T_cw;
    T.t = -(T.R * (c0 + 1.25 * (centre(T) - c0)));
  }
  const double scaled = vo::marginal_prior_energy(s, s.prior);
  restore();
  // One keyframe 3 cm to the side (its neighbours ~0.3 m away): a change of shape.
  {
    vo::Se3& T = s.kf[s.order[1]].T_cw;
    T.t = -(T.R * (centre(T) + T.R.transpose() * vo::Vec3(0.03, 0, 0)));
  }
  const double reshaped = vo::marginal_prior_energy(s, s.prior);
  restore();
  INFO("prior energy: at its linearisation point " << at_linearisation << ", window scaled by 1.25 " << scaled
                                                   << ", one keyframe moved 3 cm " << reshaped);
  CHECK(reshaped > 1.0);
  CHECK(std::fabs(at_linearisation) < 1e-6 * reshaped);
  CHECK(std::fabs(scaled) < 1e-6 * reshaped);
}
