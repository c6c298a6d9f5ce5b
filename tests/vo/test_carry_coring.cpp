// The ir modes' tracking image with the carry-over correction cored (VoConfig::carry_coring):
// street/drive frames (3 x 3 rays) through the two-frame bolometer model (tau 12 ms, 60 Hz,
// alpha = beta = 0.50) with white noise of 3 counts, compared with the true scene at the static
// level. The full correction (coring 0, the paper's) multiplies the noise by
// sqrt(1 + alpha^2) / (1 - alpha) = 2.24 everywhere; cored, the pixels where the image does not
// change keep about the raw frame's noise, and where it changes by far more than the noise the
// ghost is still taken out.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/arena.hpp"
#include "rendered_pair.hpp"
#include "state.hpp"
#include "tau_truth_feed.hpp"

using namespace bolo;

namespace {

struct TrackingImageError {
  double still = 0, moving = 0, raw_moving = 0;  // rms against the true scene, counts
};

TrackingImageError tracking_image_error(float coring) {
  test::RenderedSequence seq{"street", "drive", 160, 120, 3};
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height;
  cfg.camera = seq.intrinsics();
  cfg.photometric = vo::Photometric::ir;
  cfg.tau_init_s = 0.012f;
  cfg.carry_coring = coring;
  cfg.smoothing = 0;  // the scene estimate itself, against the true scene: no low-pass after it
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Arena arena(memory);
  vo::State* s = vo::lay_out(cfg, arena);
  REQUIRE(s != nullptr);

  const double fps = 60, te = 0.5 / fps, tr = 0.5 / fps, tau = 0.012, sigma = 3.0;
  const double alpha = std::exp(-tr / tau), beta = 1 - std::exp(-te / tau);
  const double static_level = beta / (1 - alpha);
  const std::size_t n = std::size_t{seq.width} * seq.height;
  test::ApproxNormal normal(777);
  // The scene of the last kHistory frames, newest first: a pixel whose scene held still over them
  // carries less than alpha^4 = 6 % of any older change.
  constexpr int kHistory = 5;
  std::vector<std::vector<double>> scene(kHistory, std::vector<double>(n));
  std::vector<double> y(n);
  {
    const auto u = seq.frame(1.0 - 1 / fps);
    for (std::size_t i = 0; i < n; ++i) y[i] = static_level * u[i];
    for (auto& frame : scene) frame.assign(u.begin(), u.end());
  }
  TrackingImageError e;
  double still_n = 0, moving_n = 0;
  constexpr int kFrames = 12, kMeasuredFrom = 4;  // the noise is measured from the third frame on
  for (int k = 0; k < kFrames; ++k) {
    const double t = 1.0 + k / fps;
    const auto u = seq.frame(t);
    std::rotate(scene.rbegin(), scene.rbegin() + 1, scene.rend());
    scene[0].assign(u.begin(), u.end());
    test::push_truth_frame(*s, k, te, tr, t, seq.T_cw(t), [&](std::span<float> raw) {
      for (std::size_t i = 0; i < n; ++i) {
        y[i] = alpha * y[i] + beta * u[i];
        raw[i] = static_cast<float>(std::round(y[i] + sigma * normal()));
      }
    });
    if (k < kMeasuredFrom) continue;
    const float* image = s->current.frame.level[0].value.data;
    for (std::size_t i = 0; i < n; ++i) {
      const double truth = static_level * scene[0][i];
      double held = 0;
      for (int h = 1; h < kHistory; ++h) held = std::max(held, static_level * std::fabs(scene[h][i] - scene[0][i]));
      const double change = static_level * std::fabs(scene[0][i] - scene[1][i]);
      const double d = image[i] - truth, d_raw = s->current.raw[i] - truth;
      if (held < 0.5 * sigma) e.still += d * d, ++still_n;
      if (change > 20 * sigma) e.moving += d * d, e.raw_moving += d_raw * d_raw, ++moving_n;
    }
  }
  REQUIRE(still_n > 2000);
  REQUIRE(moving_n > 500);
  e.still = std::sqrt(e.still / still_n);
  e.moving = std::sqrt(e.moving / moving_n);
  e.raw_moving = std::sqrt(e.raw_moving / moving_n);
  return e;
}

}  // namespace

TEST_CASE("coring the carry-over correction keeps still pixels at the raw noise and still deghosts moving edges",
          "[vo][ir][coring]") {
  const TrackingImageError full = tracking_image_error(0.0f);
  const TrackingImageError cored = tracking_image_error(1.0f);
  const TrackingImageError strong = tracking_image_error(2.0f);
  INFO("still pixels: full " << full.still << ", cored 1: " << cored.still << ", cored 2: " << strong.still);
  INFO("moving edges: full " << full.moving << ", cored 1: " << cored.moving << ", cored 2: " << strong.moving
                             << ", raw " << full.raw_moving);
  const double sigma = std::sqrt(9.0 + 1.0 / 12.0);
  // The full correction's inverse filter: 2.24 sigma where nothing changes; cored, close to the
  // raw frame's sigma.
  CHECK(full.still == Approx(2.24 * sigma).epsilon(0.1));
  CHECK(cored.still < 1.5 * sigma);
  CHECK(strong.still < 1.15 * sigma);
  // Where the image changes, the ghost is still taken out: far below the raw frame's error, and
  // each pixel keeps at most the cored part of its correction, coring x sqrt(2) sigma x
  // alpha / (1 - alpha) (= 1 here).
  CHECK(full.moving < 0.1 * full.raw_moving);
  CHECK(cored.moving < full.moving + 1.0 * std::sqrt(2.0) * sigma);
  CHECK(strong.moving < full.moving + 2.0 * std::sqrt(2.0) * sigma);
}
