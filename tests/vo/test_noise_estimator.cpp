// The VO's temporal-noise estimate (noise_estimator.cpp), which the tau estimator's noise-bias
// correction stands on: street/drive frames (3 x 3 rays) through the two-frame bolometer model
// (tau 12 ms), with a fixed per-pixel offset pattern, row offsets that change every frame and
// white noise of known sigma added. The fixed pattern and the row offsets are not temporal pixel
// noise and must not be counted; the moving texture must not either. A fixed pattern hides which
// blocks are flat in the scene, so some moving texture is counted there: its bound is looser.

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

double measured_sigma(double white_sigma, double row_sigma, double fixed_pattern) {
  test::RenderedSequence seq{"street", "drive", 160, 120, 3};
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height;
  cfg.camera = seq.intrinsics();
  cfg.photometric = vo::Photometric::ir;
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Arena arena(memory);
  vo::State* s = vo::lay_out(cfg, arena);
  REQUIRE(s != nullptr);

  const double fps = 60, te = 0.5 / fps, tr = 0.5 / fps, tau = 0.012;
  const double alpha = std::exp(-tr / tau), beta = 1 - std::exp(-te / tau);
  const std::size_t n = std::size_t{seq.width} * seq.height;
  test::ApproxNormal normal(4242);
  std::vector<double> offset(n);
  for (double& o : offset) o = fixed_pattern * normal();
  std::vector<double> y(n);
  {
    const auto u = seq.frame(1.0 - 1 / fps);
    for (std::size_t i = 0; i < n; ++i) y[i] = u[i];
  }
  for (int k = 0; k < 40; ++k) {
    const double t = 1.0 + k / fps;
    const auto u = seq.frame(t);
    test::push_truth_frame(*s, k, te, tr, t, seq.T_cw(t), [&](std::span<float> raw) {
      for (std::uint32_t row = 0; row < seq.height; ++row) {
        const double row_offset = row_sigma * normal();
        for (std::uint32_t col = 0; col < seq.width; ++col) {
          const std::size_t i = std::size_t{row} * seq.width + col;
          y[i] = alpha * y[i] + beta * u[i];
          raw[i] = static_cast<float>(std::round(y[i] + offset[i] + row_offset + white_sigma * normal()));
        }
      }
    });
  }
  return std::sqrt(s->noise.var);
}

}  // namespace

TEST_CASE("the VO measures the temporal pixel noise of a moving textured scene", "[vo][tau][noise][long]") {
  for (const double sigma : {2.0, 3.0, 6.0}) {
    // Whole counts add 1/12 count^2 of rounding noise.
    const double expected = std::sqrt(sigma * sigma + 1.0 / 12.0);
    const double plain = measured_sigma(sigma, 0, 0);
    const double patterned = measured_sigma(sigma, 3.0, 20.0);
    INFO("white sigma " << sigma << ": measured " << plain << ", with fixed and row patterns " << patterned);
    CHECK(std::fabs(plain - expected) < 0.05 * expected);
    CHECK(std::fabs(patterned - expected) < 0.1 * expected);
  }
}
