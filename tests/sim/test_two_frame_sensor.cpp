// The forward sensor model and the corrector are inverses: what the model ghosts, the
// corrector (float reference and fixed-point firmware alike) restores to the scene.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "bolo/sim/corrector_reference.hpp"
#include "bolo/sim/demo_scene.hpp"
#include "bolo/sim/two_frame_sensor.hpp"

using namespace bolo;

TEST_CASE("corrector inverts the forward model", "[sim]") {
  constexpr std::uint32_t W = 64, H = 48;
  const double tau_h = 0.011, tau_c = 0.013, te = 0.008, tr = 0.0087;
  sim::TwoFrameSensor::Options opt;
  opt.tau_h_s = tau_h;
  opt.tau_c_s = tau_c;
  opt.bits = 16;
  sim::TwoFrameSensor sensor(W, H, opt);

  fw::CorrectorConfig cfg;
  cfg.width = W;
  cfg.height = H;
  cfg.tau = {11'000'000, 13'000'000};
  std::vector<fw::Pixel> storage(fw::TwoFrameCorrector::storage_pixels(W, H));
  bolo::test::HashingCollector sink(W, H);
  fw::TwoFrameCorrector corrector(cfg, storage, sink);

  std::vector<float> scene(W * H);
  std::vector<std::uint16_t> raw(W * H), previous;
  std::vector<double> restored(W * H);
  double worst_float = 0, worst_fixed = 0, worst_raw = 0;
  for (int i = 0; i < 30; ++i) {
    const double t = i / 60.0;
    sim::render_demo_scene(W, H, t, {}, scene);
    sensor.expose(scene, {te, tr}, i == 0, raw);
    fw::FrameHeader hd;
    hd.width = W;
    hd.height = H;
    hd.sequence = static_cast<std::uint64_t>(i);
    hd.sequence_valid = true;
    hd.exposure_ns = 8'000'000;
    hd.readout_ns = 8'700'000;
    bolo::test::push_frame(corrector, hd, raw);
    if (i > 0) {
      sim::correct_frame_reference(raw, previous, tau_h, tau_c, te, tr, restored);
      for (std::size_t p = 0; p < scene.size(); ++p) {
        worst_float = std::max(worst_float, std::abs(restored[p] - scene[p]));
        worst_fixed = std::max(worst_fixed, std::abs(sink.frame()[p] - double{scene[p]}));
        const double heat = 1 - std::exp(-te / tau_h);
        worst_raw = std::max(worst_raw, std::abs(raw[p] / heat - scene[p]));
      }
    }
    previous = raw;
  }
  INFO("worst error vs scene: raw/heat " << worst_raw << ", float " << worst_float << ", fixed "
                                          << worst_fixed);
  // Quantising the raw frames to integers costs up to 0.5 count, amplified by g and a*g.
  const double g = 1 / (1 - std::exp(-te / tau_h));
  const double bound = 0.5 * g * (1 + std::exp(-tr / tau_c)) + 0.5;
  CHECK(worst_raw > 100);  // there is ghosting to correct
  CHECK(worst_float <= bound);
  CHECK(worst_fixed <= bound + 1);
}
