// The tau estimator (ir modes) against truth: frames rendered in-process go through the
// two-frame bolometer model with tau = 12 ms; with the true poses and depths, the online
// estimate started at 8 ms must come within 10 % of the truth within 2 s of frames.
// Hidden ([.]): it fails today (the estimate drifts to ~4.5 ms), see docs/odometry-study.md.

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/arena.hpp"
#include "rendered_pair.hpp"
#include "state.hpp"

using namespace bolo;

namespace {
double estimate_after_2s(unsigned supersample) {
  test::RenderedSequence seq{"street", "drive", 160, 120, supersample};
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height;
  cfg.camera = seq.intrinsics();
  cfg.photometric = vo::Photometric::ir;
  cfg.tau_init_s = 0.008f;
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Arena arena(memory);
  vo::State* s = vo::lay_out(cfg, arena);
  if (s == nullptr) return 0;

  const double fps = 60, te = 0.5 / fps, tr = 0.5 / fps, tau = 0.012;
  const double alpha = std::exp(-tr / tau), beta = 1 - std::exp(-te / tau);
  const std::size_t n = std::size_t{seq.width} * seq.height;
  std::vector<double> y(n);
  const double t0 = 1.0;
  {
    const auto u = seq.frame(t0 - 1 / fps);
    for (std::size_t i = 0; i < n; ++i) y[i] = u[i];  // settled
  }
  vo::Keyframe* kf = nullptr;
  double estimate_2s = 0;
  for (int k = 0; k <= 120; ++k) {
    const double t = t0 + k / fps;
    const auto u = seq.frame(t);
    std::swap(s->raw, s->raw_prev);
    for (std::size_t i = 0; i < n; ++i) {
      y[i] = alpha * y[i] + beta * u[i];
      s->raw[i] = static_cast<float>(y[i]);
    }
    s->have_prev = k > 0;
    s->chain_ok = k > 0;
    s->exposure_s = te, s->readout_prev_s = tr, s->t_s = t;
    s->T_cw = seq.T_cw(t);
    if (k % 12 == 1) {
      // A new keyframe every 12 frames, its points at their true depth.
      for (std::size_t i = 0; i < n; ++i) s->frame.level[0].value.data[i] = s->raw[i];
      vo::build_pyramid(s->frame);
      const std::uint32_t slot = vo::new_keyframe_slot(*s);
      vo::make_keyframe(*s, slot, true);
      kf = &s->kf[slot];
      for (std::uint32_t i = 0; i < kf->count; ++i) {
        vo::Point& p = kf->points[i];
        const double z = seq.depth(t, p.u, p.v);
        p.status = z > 0 && z < 150 ? vo::PointStatus::active : vo::PointStatus::empty;
        p.idepth = static_cast<float>(1 / z);
        p.inlier = true;
      }
      continue;
    }
    if (kf) vo::refine_tau(*s);
    if (k == 120) estimate_2s = s->tau.c;
  }
  return estimate_2s;
}
}  // namespace

TEST_CASE("tau estimate converges to the bolometer's time constant with true geometry", "[.][vo][tau]") {
  const double estimate = estimate_after_2s(1);
  INFO("tau_c after 2 s: " << estimate * 1e3 << " ms (truth 12 ms, start 8 ms)");
  CHECK(std::fabs(estimate - 0.012) < 0.1 * 0.012);
}
