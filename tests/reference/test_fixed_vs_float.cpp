// The fixed-point corrector against its floating-point reference in sim/: within 1 LSB on
// random and edge inputs over a grid of timings, and on every frame of the shared recordings.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "../test_support.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/sim/corrector_reference.hpp"

using namespace bolo;
using bolo::test::SplitMix64;

TEST_CASE("fixed within 1 LSB of float on random and edge inputs", "[reference]") {
  SplitMix64 rng(2024);
  std::vector<fw::Pixel> cur, prev;
  const std::vector<fw::Pixel> edges = {0, 1, 100, 8191, 16383, 32768, 60000, 65534, 65535};
  for (auto a : edges)
    for (auto b : edges) {
      cur.push_back(a);
      prev.push_back(b);
    }
  for (int i = 0; i < 3000; ++i) {
    cur.push_back(static_cast<fw::Pixel>(rng.next()));
    prev.push_back(static_cast<fw::Pixel>(rng.next()));
    const auto base = static_cast<fw::Pixel>(rng.below(16384));  // 14-bit scenes, small steps
    cur.push_back(base);
    prev.push_back(static_cast<fw::Pixel>(base + rng.below(200)));
  }
  std::vector<fw::Pixel> fixed(cur.size());
  std::vector<double> ref(cur.size());
  double worst = 0;
  int combos = 0;
  for (double tau_h : {0.008, 0.010, 0.012, 0.015}) {
    for (double tau_c : {0.008, 0.012, 0.015}) {
      for (double te : {0.002, 0.005, 0.008, 0.010, 0.016}) {
        for (double tr : {0.0001, 0.001, 0.004, 0.008, 0.0167, 0.1}) {
          fw::CorrectorCoefficients c;
          const auto status = fw::compute_coefficients(
              {static_cast<std::uint32_t>(std::lround(tau_h * 1e9)),
               static_cast<std::uint32_t>(std::lround(tau_c * 1e9))},
              static_cast<std::uint32_t>(std::lround(te * 1e9)),
              static_cast<std::uint32_t>(std::lround(tr * 1e9)), c);
          REQUIRE(status == fw::CoefficientStatus::ok);
          std::uint32_t low = 0, high = 0;
          fw::correct_line(cur.data(), prev.data(), c, fixed.data(), cur.size(), low, high);
          sim::correct_frame_reference(cur, prev, tau_h, tau_c, te, tr, ref);
          for (std::size_t i = 0; i < cur.size(); ++i)
            worst = std::max(worst, std::abs(fixed[i] - ref[i]));
          ++combos;
        }
      }
    }
  }
  INFO(combos << " timing combinations, worst |fixed - float| = " << worst);
  CHECK(worst <= 1.0);
}

namespace {

// Collects each corrected frame and compares it with the reference as it completes.
class Comparer final : public fw::LineSink {
 public:
  Comparer(rec::Recording& reader, sim::ReferenceCorrector& ref,
           const fw::TwoFrameCorrector* const& corrector)
      : collector_(reader.width(), reader.height()), reader_(reader), ref_(ref),
        corrector_(corrector), input_(std::size_t{reader.width()} * reader.height()),
        expected_(input_.size()) {}
  void begin_frame(const fw::FrameHeader& hd) override { collector_.begin_frame(hd); }
  void push_line(std::uint32_t row, fw::LineView line) override { collector_.push_line(row, line); }
  void end_frame() override {
    collector_.end_frame();
    const std::uint64_t index = collector_.header().sequence;
    const rec::FrameRow& row = reader_.rows()[index];
    const sim::ReferenceFrameInfo info{row.index, row.t_s, row.exposure_s, row.readout_s,
                                       row.ffc.value_or(false)};
    reader_.read_frame(index, input_);
    const bool applied = ref_.process(info, input_, expected_);
    const bool fixed_applied = corrector_->last_frame().carry_over == fw::CarryOver::applied;
    if (applied != fixed_applied) ++decision_mismatches;
    if (applied) ++applied_frames;
    for (std::size_t i = 0; i < input_.size(); ++i)
      worst = std::max(worst, std::abs(collector_.frame()[i] - expected_[i]));
    ++frames;
  }
  double worst = 0;
  int decision_mismatches = 0, applied_frames = 0, frames = 0;

 private:
  bolo::test::HashingCollector collector_;
  rec::Recording& reader_;
  sim::ReferenceCorrector& ref_;
  const fw::TwoFrameCorrector* const& corrector_;
  std::vector<fw::Pixel> input_;
  std::vector<double> expected_;
};

}  // namespace

TEST_CASE("fixed within 1 LSB of float on every frame of the shared recordings", "[reference][shared]") {
  struct Timing {
    double tau_h, tau_c, exposure, readout;
  };
  for (const char* name : {"lepton3-possum", "lepton35-trailcam-ffc", "flirone-lepton-telemetry",
                           "flir-t1030-hand"}) {
    const auto dir = bolo::test::shared_recording(name);
    if (dir.empty()) return;  // skipped: no shared data
    // The reference settings, and a 60 Hz-like timing with a strong carry-over term.
    for (const Timing t : {Timing{0.012, 0.012, 0.01, 0.1}, Timing{0.012, 0.010, 0.008, 0.0087}}) {
      hal::RecordingPlayer player(dir);
      rec::Recording reader(dir);
      const auto format = player.format();
      fw::PipelineConfig cfg;
      cfg.corrector.width = format.width;
      cfg.corrector.height = format.height;
      cfg.corrector.tau = {static_cast<std::uint32_t>(std::lround(t.tau_h * 1e9)),
                           static_cast<std::uint32_t>(std::lround(t.tau_c * 1e9))};
      cfg.corrector.default_exposure_ns = static_cast<std::uint32_t>(std::lround(t.exposure * 1e9));
      cfg.corrector.default_readout_ns = static_cast<std::uint32_t>(std::lround(t.readout * 1e9));
      sim::ReferenceCorrector ref(format.width, format.height, t.tau_h, t.tau_c, t.exposure,
                                  t.readout, std::nullopt);
      const fw::TwoFrameCorrector* corrector = nullptr;
      Comparer comparer(reader, ref, corrector);
      std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(cfg));
      fw::Pipeline pipeline(cfg, arena, comparer);
      corrector = &pipeline.corrector();
      while (player.stream_frame(pipeline.input()) == hal::StreamStatus::frame) {
      }
      INFO(name << " tau_h " << t.tau_h << " tau_c " << t.tau_c << " t_e " << t.exposure
                << " t_r " << t.readout << ": " << comparer.frames << " frames, "
                << comparer.applied_frames << " with carry-over, worst |fixed - float| = "
                << comparer.worst);
      CHECK(comparer.frames == static_cast<int>(reader.frame_count()));
      CHECK(comparer.decision_mismatches == 0);
      CHECK(comparer.applied_frames > 0);
      CHECK(comparer.worst <= 1.0);
    }
  }
}
