// Golden vectors on synthetic inputs: the corrector alone and the full pipeline, over sizes,
// time constants, timings, edge images (0, max, steps, checkerboards, saturation) and chain
// breaks (drops, FFC, time gaps). Set BOLO_GOLDEN_PRINT=1 to print the current hashes.

#include <catch2/catch.hpp>

#include <cstdlib>
#include <functional>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "golden_cases.hpp"

using namespace bolo;
using bolo::test::SplitMix64;

namespace {

enum class Pattern { random, zeros, max, steps, checker, ramp, hot_spot };

void fill(std::vector<fw::Pixel>& f, std::uint32_t w, std::uint32_t h, Pattern p,
          std::uint64_t frame, SplitMix64& rng) {
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      fw::Pixel v = 0;
      switch (p) {
        case Pattern::random: v = static_cast<fw::Pixel>(rng.next()); break;
        case Pattern::zeros: v = 0; break;
        case Pattern::max: v = 0xFFFF; break;
        case Pattern::steps: v = static_cast<fw::Pixel>(((x + frame * 3) / 8 % 2) ? 60000 : 200); break;
        case Pattern::checker: v = ((x + y + frame) % 2) ? 0xFFFF : 0; break;
        case Pattern::ramp: v = static_cast<fw::Pixel>((x * 65535ull) / (w > 1 ? w - 1 : 1)); break;
        case Pattern::hot_spot:
          v = static_cast<fw::Pixel>(8000 + rng.below(50) +
                                     ((x / 4 == frame % (w / 4 + 1) && y > h / 3) ? 7000 : 0));
          break;
      }
      f[std::size_t{y} * w + x] = v;
    }
}

struct Case {
  std::string name;
  std::uint32_t w, h;
  fw::TimeConstants tau;
  std::uint32_t exposure_ns, readout_ns;
  Pattern pattern;
  bool full_pipeline;
  std::uint64_t frames = 12;
  // Per-frame timing jitter (ns per frame index): many distinct coefficients, so a change in the
  // rounding of any coefficient shows up in the hashes.
  std::uint32_t jitter_ns = 0;
};

std::uint64_t run_case(const Case& c) {
  SplitMix64 rng(0xB010 + c.w * 131 + c.h);
  std::vector<std::uint16_t> gain(std::size_t{c.w} * c.h);
  std::vector<std::int16_t> offset(gain.size());
  std::vector<std::uint8_t> mask(gain.size(), 0);
  for (auto& g : gain) g = static_cast<std::uint16_t>(fw::kNucUnityGain - 1500 + rng.below(3000));
  for (auto& o : offset) o = static_cast<std::int16_t>(static_cast<int>(rng.below(400)) - 200);
  for (std::size_t i = 0; i < mask.size(); i += 37) mask[i] = 1;

  fw::PipelineConfig cfg;
  cfg.corrector.width = c.w;
  cfg.corrector.height = c.h;
  cfg.corrector.tau = c.tau;
  cfg.use_nuc = c.full_pipeline;
  cfg.nuc = {gain, offset};
  cfg.use_bad_pixels = c.full_pipeline;
  cfg.bad_pixels.mask = mask;
  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(cfg));
  bolo::test::HashingCollector sink(c.w, c.h);
  fw::Pipeline pipeline(cfg, arena, sink);

  std::vector<fw::Pixel> frame(std::size_t{c.w} * c.h);
  std::int64_t t = 0;
  std::uint64_t seq = 0;
  for (std::uint64_t i = 0; i < c.frames; ++i) {
    fill(frame, c.w, c.h, c.pattern, i, rng);
    fw::FrameHeader hd;
    hd.width = c.w;
    hd.height = c.h;
    hd.sequence = seq;
    hd.sequence_valid = true;
    hd.timestamp_ns = t;
    hd.timestamp_valid = true;
    hd.exposure_ns = c.exposure_ns + static_cast<std::uint32_t>(i) * c.jitter_ns;
    hd.readout_ns = c.readout_ns + static_cast<std::uint32_t>(i) * c.jitter_ns * 3;
    hd.ffc = i == 7 ? fw::FfcState::completed : fw::FfcState::none;
    bolo::test::push_frame(pipeline.input(), hd, frame);
    seq += i == 4 ? 2 : 1;                                            // a drop after frame 4
    t += std::int64_t{c.exposure_ns} + c.readout_ns + (i == 9 ? 90'000'000 : 0);  // a time gap
  }
  return sink.hash();
}

std::vector<Case> cases() {
  const fw::TimeConstants t12{12'000'000, 12'000'000};
  return {
      {"corrector_160x120_random_tau12", 160, 120, t12, 10'000'000, 6'666'667, Pattern::random, false},
      {"corrector_160x120_hotspot_tau8_15", 160, 120, {8'000'000, 15'000'000}, 8'000'000, 8'666'667, Pattern::hot_spot, false},
      {"corrector_80x60_steps_tau15", 80, 60, {15'000'000, 15'000'000}, 16'000'000, 100'000'000, Pattern::steps, false},
      {"corrector_33x7_checker_saturating", 33, 7, t12, 2'000'000, 500'000, Pattern::checker, false},
      {"corrector_17x5_zeros", 17, 5, t12, 10'000'000, 6'000'000, Pattern::zeros, false},
      {"corrector_17x5_max", 17, 5, t12, 10'000'000, 6'000'000, Pattern::max, false},
      {"corrector_64x8_ramp_tau1", 64, 8, {1'000'000, 1'000'000}, 10'000'000, 100'000, Pattern::ramp, false},
      {"corrector_640x512_hotspot_60hz", 640, 512, t12, 8'000'000, 8'666'667, Pattern::hot_spot, false, 5},
      {"pipeline_160x120_hotspot", 160, 120, t12, 10'000'000, 6'666'667, Pattern::hot_spot, true},
      {"pipeline_80x60_random", 80, 60, {9'000'000, 14'000'000}, 11'000'000, 5'000'000, Pattern::random, true},
      {"pipeline_31x9_checker", 31, 9, t12, 3'000'000, 1'000'000, Pattern::checker, true},
      {"corrector_160x120_hotspot_jittered_timing", 160, 120, t12, 7'000'000, 5'000'000, Pattern::hot_spot, false, 48, 1'237},
      {"corrector_80x60_random_jittered_timing", 80, 60, {10'000'000, 13'000'000}, 9'000'000, 4'000'000, Pattern::random, false, 48, 3'301},
  };
}

}  // namespace

TEST_CASE("synthetic golden vectors", "[golden]") {
  const auto golden = bolo::test::read_golden(std::string(BOLO_TESTS_DIR) + "/golden/synthetic.golden");
  const bool print = std::getenv("BOLO_GOLDEN_PRINT") != nullptr;
  for (const Case& c : cases()) {
    const std::string hash = bolo::test::hex64(run_case(c));
    if (print) std::printf("%s %s\n", c.name.c_str(), hash.c_str());
    INFO("case " << c.name << ": got " << hash);
    CHECK(golden.count(c.name) == 1);
    if (golden.count(c.name) == 1) CHECK(golden.at(c.name) == hash);
  }
}
