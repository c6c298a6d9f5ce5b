// Proves the firmware pipeline allocates nothing after initialisation: malloc and operator new
// are replaced in this binary by counting versions, and 1000 frames stream through NUC,
// bad-pixel replacement and the two-frame corrector from a frame source (the HAL interface).

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "frame_collector.hpp"

#include "counting_allocator.hpp"  // replaces malloc/new in this binary

using bolo::test::g_allocations;
using bolo::test::g_counting;

namespace {

using namespace bolo;

// Frames made on the fly into one preallocated buffer: a moving hot bar over a noisy
// background, an FFC event every 250 frames and a dropped frame every 97.
class SyntheticSource final : public hal::FrameSource {
 public:
  SyntheticSource(std::uint32_t w, std::uint32_t h, std::uint64_t frames)
      : w_(w), h_(h), frames_(frames), line_(w), rng_(1) {}
  hal::SourceFormat format() const override { return {w_, h_, 14, hal::PixelUnits::counts, 33'333'333}; }
  hal::SourceStats stats() const override { return stats_; }
  hal::StreamStatus stream_frame(fw::LineSink& sink) override {
    if (next_ >= frames_) return hal::StreamStatus::end_of_stream;
    if (next_ % 97 == 96) ++next_;  // a drop: the counter skips
    fw::FrameHeader hd;
    hd.width = w_;
    hd.height = h_;
    hd.sequence = next_;
    hd.sequence_valid = true;
    hd.timestamp_ns = static_cast<std::int64_t>(next_) * 33'333'333;
    hd.timestamp_valid = true;
    hd.exposure_ns = 8'000'000;
    hd.readout_ns = 25'000'000;
    hd.ffc = next_ % 250 == 0 && next_ > 0 ? fw::FfcState::completed : fw::FfcState::none;
    sink.begin_frame(hd);
    const std::uint32_t bar = static_cast<std::uint32_t>(next_ % w_);
    for (std::uint32_t r = 0; r < h_; ++r) {
      for (std::uint32_t x = 0; x < w_; ++x)
        line_[x] = static_cast<fw::Pixel>(3000 + rng_.below(64) + (x == bar ? 6000 : 0));
      if (r == 5) line_[9] = 0x3FFF;  // a stuck pixel
      sink.push_line(r, fw::LineView(line_.data(), w_));
    }
    sink.end_frame();
    ++next_;
    ++stats_.frames_delivered;
    return hal::StreamStatus::frame;
  }

 private:
  std::uint32_t w_, h_;
  std::uint64_t frames_, next_ = 0;
  std::vector<fw::Pixel> line_;
  bolo::test::SplitMix64 rng_;
  hal::SourceStats stats_;
};

int failures = 0;
void check(bool ok, const char* what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAILED", what);
  if (!ok) ++failures;
}

}  // namespace

int main() {
  if (!BOLO_COUNTING_ALLOCATOR_ACTIVE) {
    std::printf("SKIPPED: a sanitizer owns malloc in this build; heap allocations cannot be counted\n");
    return bolo::test::kSkipExitCode;
  }
  // The counter must see what it is meant to see, or a zero below would prove nothing.
  g_counting = true;
  {
    std::vector<int>* probe = new std::vector<int>(100);
    bolo::test::g_escape = probe;
    delete probe;
    void* raw = std::malloc(64);
    bolo::test::g_escape = raw;
    std::free(raw);
  }
  g_counting = false;
  check(g_allocations.load() == 3, "the counting allocator sees new and malloc");
  g_allocations = 0;

  constexpr std::uint32_t W = 160, H = 120;
  std::vector<std::uint16_t> gain(W * H, fw::kNucUnityGain);
  std::vector<std::int16_t> offset(W * H, -100);
  std::vector<std::uint8_t> mask(W * H, 0);
  mask[40 * W + 40] = 1;

  fw::PipelineConfig cfg;
  cfg.corrector.width = W;
  cfg.corrector.height = H;
  cfg.corrector.tau = {12'000'000, 12'000'000};
  cfg.use_nuc = true;
  cfg.nuc = {gain, offset};
  cfg.use_bad_pixels = true;
  cfg.bad_pixels.mask = mask;
  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(cfg));
  bolo::test::HashingCollector sink(W, H);
  fw::Pipeline pipeline(cfg, arena, sink);
  SyntheticSource source(W, H, 1000);

  // Initialisation is over: from here on nothing may allocate.
  g_counting = true;
  std::uint64_t frames = 0;
  while (source.stream_frame(pipeline.input()) == hal::StreamStatus::frame) ++frames;
  g_counting = false;

  const long allocations = g_allocations.load();
  std::printf("streamed %llu frames of %ux%u, heap allocations after init: %ld\n",
              static_cast<unsigned long long>(frames), W, H, allocations);
  check(frames == 990, "1000-frame stream (10 dropped by the source) went through");
  check(sink.frames() == frames, "every frame reached the sink");
  check(allocations == 0, "zero heap allocations after initialisation");
  const auto& totals = pipeline.corrector().totals();
  check(totals.by_reason[static_cast<int>(fw::CarryOver::sequence_gap)] == 10, "10 drops seen");
  check(totals.by_reason[static_cast<int>(fw::CarryOver::ffc_event)] == 3, "3 FFC events seen");
  std::printf("%d passed, %d failed\n", 7 - failures, failures);
  return failures == 0 ? 0 : 1;
}
