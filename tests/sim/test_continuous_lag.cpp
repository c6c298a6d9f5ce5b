// The simulator's continuous lag (PixelLag::continuous): a first-order lag through the whole frame
// period, read at its end. Its frames.csv timing gives the two-frame model's coefficients exactly,
// and a moving edge reads what the lag integrated by hand over the period reads.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "bolo/sim/simulator.hpp"
#include "bolo/sim/two_frame_sensor.hpp"

using namespace bolo;

namespace {

constexpr double kLagFps = 60.0, kLagTau = 0.010;

sim::SimulatorConfig continuous_lag_config(std::uint32_t width, std::uint32_t substeps) {
  sim::SimulatorConfig c;
  c.info.width = width;
  c.info.height = 2;
  c.info.bits = 16;
  c.info.fps = kLagFps;
  c.info.exposure_s = c.info.readout_s = 1.0 / kLagFps;
  c.info.tau_h_s = c.info.tau_c_s = kLagTau;
  c.lag = sim::PixelLag::continuous;
  c.substeps = substeps;
  c.noise_counts = 0.0;
  return c;
}

}  // namespace

TEST_CASE("continuous lag: a static step follows y_i = alpha y_(i-1) + beta u with alpha = exp(-T/tau)",
          "[sim][physics]") {
  const double T = 1.0 / kLagFps, before = 2000.0, after = 9000.0;
  constexpr int step_frame = 3;
  // The scene changes at the start of frame 3's period and is constant within every period.
  sim::Simulator simulator(continuous_lag_config(4, 8), [&](double t, std::span<float> out) {
    std::fill(out.begin(), out.end(), static_cast<float>(t < step_frame * T ? before : after));
  });
  const double alpha = std::exp(-T / kLagTau), beta = 1.0 - alpha;
  double y = before;  // settled before frame 0
  sim::SimulatedFrame frame;
  for (int i = 0; i < 10; ++i) {
    simulator.next(frame);
    REQUIRE(frame.row.exposure_s);
    REQUIRE(frame.row.readout_s);
    CHECK(*frame.row.exposure_s == Approx(T).epsilon(1e-12));
    CHECK(*frame.row.readout_s == Approx(T).epsilon(1e-12));
    // frames.csv's timing gives the lag's own coefficients through the two-frame model's definition.
    const sim::FrameCoefficients k = sim::frame_coefficients(*frame.row.exposure_s, *frame.row.readout_s, kLagTau, kLagTau);
    CHECK(k.carry == Approx(alpha).epsilon(1e-12));
    CHECK(k.heat == Approx(beta).epsilon(1e-12));
    // Read at the end of its period: the frame's time and its pose's.
    CHECK(*frame.row.t_s == Approx((i + 1) * T).epsilon(1e-12));
    CHECK(frame.pose_t_s == *frame.row.t_s);
    y = alpha * y + beta * (i < step_frame ? before : after);
    for (std::uint16_t v : frame.counts) CHECK(std::abs(v - y) <= 0.5 + 1e-9);  // output rounded to counts
  }
}

TEST_CASE("continuous lag: a moving edge reads the lag integrated over the whole period", "[sim][physics]") {
  constexpr std::uint32_t K = 8, W = 3 * K;
  const double T = 1.0 / kLagFps, d = T / K, hot = 8000.0, cold = 1500.0;
  const double start = 2 * T;  // two still frames, then pixel p turns cold at start + p d
  // One pixel a sub-step: every switch falls on a sub-step boundary, so sampling the scene at the
  // sub-steps' centres is exact and the hand integral below owes nothing to K.
  const auto cold_from = [&](std::uint32_t p) { return start + p * d; };
  sim::Simulator simulator(continuous_lag_config(W, K), [&](double t, std::span<float> out) {
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = static_cast<float>(t < cold_from(static_cast<std::uint32_t>(i % W)) ? hot : cold);
  });
  std::vector<double> y(W, hot);
  sim::SimulatedFrame frame;
  double worst = 0.0;
  for (int i = 0; i < 6; ++i) {
    simulator.next(frame);
    const double t1 = *frame.row.t_s, t0 = t1 - T;  // the period this frame relaxed over
    for (std::uint32_t p = 0; p < W; ++p) {
      // dy/dt = (u - y) / tau from t0 to t1, u hot until ts then cold.
      const double ts = std::clamp(cold_from(p), t0, t1);
      const double hot_part = std::exp(-(t1 - ts) / kLagTau) - std::exp(-T / kLagTau);
      y[p] = y[p] * std::exp(-T / kLagTau) + hot * hot_part + cold * (1.0 - std::exp(-(t1 - ts) / kLagTau));
      for (std::uint32_t r = 0; r < 2; ++r) worst = std::max(worst, std::abs(frame.counts[r * W + p] - y[p]));
    }
  }
  CHECK(worst <= 0.5 + 1e-6);  // the output's rounding to counts
}

TEST_CASE("continuous lag: the simulator refuses a timing that is not the period", "[sim]") {
  sim::SimulatorConfig c = continuous_lag_config(4, 4);
  c.info.exposure_s = c.info.readout_s = 0.5 / kLagFps;
  CHECK_THROWS_WITH(sim::Simulator(c, [](double, std::span<float>) {}), Catch::Contains("continuous lag"));
  c = continuous_lag_config(4, 4);
  c.info.tau_c_s = 0.012;
  CHECK_THROWS_WITH(sim::Simulator(c, [](double, std::span<float>) {}), Catch::Contains("one time constant"));
}
