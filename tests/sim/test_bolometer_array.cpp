// The continuous-time pixel model: closed-form step responses, and the paper's two-frame model as
// its special case for an input constant within each frame.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "bolo/sim/bolometer_array.hpp"
#include "bolo/sim/two_frame_sensor.hpp"

using namespace bolo;

TEST_CASE("a step inside the exposure follows the closed form", "[sim][physics]") {
  const double tau_h = 0.011, te = 0.008;
  constexpr int K = 16;
  // The input steps from 0 to U after k0 of K sub-steps.
  for (int k0 : {0, 4, 8, 15}) {
    sim::BolometerArray pixel(1, 1, tau_h, 0.012);
    const float U = 1000.0f;
    std::vector<float> off(1, 0.0f), on(1, U);
    std::vector<std::span<const float>> steps;
    for (int k = 0; k < K; ++k) steps.push_back(k < k0 ? std::span<const float>(off) : std::span<const float>(on));
    std::vector<double> y(1);
    pixel.expose(steps, te, 0.01, y);
    const double heated_for = te * (K - k0) / K;
    CHECK(y[0] == Approx(U * (1 - std::exp(-heated_for / tau_h))).epsilon(1e-12));
  }
}

TEST_CASE("cooling over the readout follows exp(-t_r / tau_c)", "[sim][physics]") {
  const double tau_c = 0.013;
  sim::BolometerArray pixel(1, 1, 0.011, tau_c);
  std::vector<float> hot(1, 500.0f), cold(1, 0.0f);
  std::vector<double> y1(1), y2(1);
  const std::span<const float> h[1] = {hot}, c[1] = {cold};
  pixel.expose(h, 0.01, 0.007, y1);
  pixel.expose(c, 0.01, 0.007, y2);  // no new heat: only the cooled residual is read
  CHECK(y2[0] == Approx(y1[0] * std::exp(-0.007 / tau_c)).epsilon(1e-12));
  pixel.reset();
  pixel.expose(c, 0.01, 0.007, y2);
  CHECK(y2[0] == 0.0);
}

TEST_CASE("the paper's two-frame model is the special case of a frame-constant input", "[sim][physics]") {
  constexpr std::uint32_t W = 7, H = 5;
  const double tau_h = 0.0095, tau_c = 0.0125;
  sim::BolometerArray array(W, H, tau_h, tau_c);
  sim::TwoFrameSensor::Options opt;
  opt.tau_h_s = tau_h;
  opt.tau_c_s = tau_c;
  opt.bits = 16;
  sim::TwoFrameSensor discrete(W, H, opt);
  std::vector<float> scene(W * H);
  std::vector<double> y(W * H);
  std::vector<std::uint16_t> d(W * H);
  double worst = 0;
  for (int i = 0; i < 20; ++i) {
    for (std::size_t p = 0; p < scene.size(); ++p)
      scene[p] = static_cast<float>(3000 + 2500 * std::sin(0.7 * i + 0.3 * static_cast<double>(p)));
    const double te = 0.006 + 0.0005 * (i % 3), tr = 0.004 + 0.001 * (i % 4);
    // The same input on every one of 8 sub-steps: the frame-constant case.
    std::vector<std::span<const float>> steps(8, std::span<const float>(scene));
    array.expose(steps, te, tr, y);
    discrete.expose(scene, {te, tr}, i == 0, d);
    for (std::size_t p = 0; p < y.size(); ++p) worst = std::max(worst, std::abs(std::round(y[p]) - d[p]));
  }
  CHECK(worst == 0.0);  // identical after the discrete model's rounding to counts
}

TEST_CASE("per-pixel time constants act per pixel", "[sim][physics]") {
  sim::BolometerArray array(2, 1, std::vector<double>{0.005, 0.020}, std::vector<double>{0.01, 0.01});
  std::vector<float> u(2, 100.0f);
  const std::span<const float> steps[1] = {u};
  std::vector<double> y(2);
  array.expose(steps, 0.01, 0.0, y);
  CHECK(y[0] == Approx(100 * (1 - std::exp(-2.0))));
  CHECK(y[1] == Approx(100 * (1 - std::exp(-0.5))));
  CHECK_THROWS(sim::BolometerArray(2, 1, std::vector<double>{0.01}, std::vector<double>{0.0}));
}
