// NUC and bad-pixel stages, line latency of every stage, and the composed pipeline.

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <vector>

#include "bolo/firmware/pipeline.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::HashingCollector;
using bolo::test::push_frame;
using bolo::test::SplitMix64;

namespace {

fw::FrameHeader header(std::uint32_t w, std::uint32_t h, std::uint64_t seq) {
  fw::FrameHeader hd;
  hd.width = w;
  hd.height = h;
  hd.sequence = seq;
  hd.sequence_valid = true;
  hd.timestamp_ns = static_cast<std::int64_t>(seq) * 100'000'000;
  hd.timestamp_valid = true;
  hd.exposure_ns = 10'000'000;
  hd.readout_ns = 6'000'000;
  hd.ffc = fw::FfcState::none;
  return hd;
}

// Records, for every output line, how many input lines had been pushed when it came out.
class LatencyProbe final : public fw::LineSink {
 public:
  explicit LatencyProbe(const std::uint32_t& inputs_pushed) : inputs_(inputs_pushed) {}
  void begin_frame(const fw::FrameHeader&) override { seen.clear(); }
  void push_line(std::uint32_t row, fw::LineView) override { seen.push_back({row, inputs_}); }
  void end_frame() override {}
  struct Event {
    std::uint32_t row, inputs_pushed;
  };
  std::vector<Event> seen;

 private:
  const std::uint32_t& inputs_;
};

}  // namespace

TEST_CASE("NUC applies a Q2.14 gain and an offset per pixel, saturating", "[nuc]") {
  constexpr std::uint32_t W = 4, H = 2;
  std::vector<std::uint16_t> gain = {fw::kNucUnityGain, 2 * fw::kNucUnityGain, fw::kNucUnityGain / 2,
                                     fw::kNucUnityGain, 3 * fw::kNucUnityGain, fw::kNucUnityGain,
                                     fw::kNucUnityGain, fw::kNucUnityGain};
  std::vector<std::int16_t> offset = {0, 0, 0, -50, 0, 100, -2000, 0};
  std::vector<fw::Pixel> storage(fw::NucStage::storage_pixels(W));
  HashingCollector sink(W, H);
  fw::NucStage nuc(W, H, {gain, offset}, storage, sink);
  push_frame(nuc, header(W, H, 0), {1000, 1000, 1001, 1000, 30000, 65500, 1000, 7});
  CHECK(sink.frame() == std::vector<fw::Pixel>{1000, 2000, 501, 950, 65535, 65535, 0, 7});
}

TEST_CASE("bad pixels are replaced by the rounded mean of their good 3x3 neighbours", "[bad_pixel]") {
  constexpr std::uint32_t W = 5, H = 4;
  std::vector<std::uint8_t> mask(W * H, 0);
  mask[1 * W + 1] = 1;  // masked
  std::vector<fw::Pixel> frame = {
      10, 20, 30, 40, 50,  //
      11, 999, 31, 41, 51,  //
      12, 22, 0, 42, 52,    // 0 is the stuck-low rail
      13, 23, 33, 43, 0x3FFF};
  fw::BadPixelConfig cfg;
  cfg.width = W;
  cfg.height = H;
  cfg.mask = mask;
  std::vector<fw::Pixel> storage(fw::BadPixelStage::storage_pixels(W, H));
  HashingCollector sink(W, H);
  fw::BadPixelStage stage(cfg, storage, sink);
  std::fill(mask.begin(), mask.end(), 0);  // the stage took the mask at construction
  push_frame(stage, header(W, H, 0), frame);
  const auto& out = sink.frame();
  // (1,1): neighbours 10 20 30 11 31 12 22 (0 at (2,2) is bad) -> 136/7 = 19.43 -> 19
  CHECK(out[1 * W + 1] == 19);
  // (2,2): neighbours 31 41 22 42 23 33 43 (999 is masked) -> 235/7 = 33.57 -> 34
  CHECK(out[2 * W + 2] == 34);
  // corner (3,4): neighbours 42 52 43 -> 137/3 = 45.67 -> 46
  CHECK(out[3 * W + 4] == 46);
  CHECK(out[0] == 10);
  CHECK(stage.last_frame().replaced == 3);
  CHECK(sink.lines() == H);
}

TEST_CASE("line latency: corrector 0 lines, bad-pixel stage its radius", "[latency]") {
  constexpr std::uint32_t W = 6, H = 5;
  std::uint32_t pushed = 0;
  LatencyProbe probe(pushed);
  std::vector<fw::Pixel> line(W, 500);

  SECTION("two-frame corrector") {
    fw::CorrectorConfig cfg;
    cfg.width = W;
    cfg.height = H;
    cfg.tau = {12'000'000, 12'000'000};
    std::vector<fw::Pixel> storage(fw::TwoFrameCorrector::storage_pixels(W, H));
    fw::TwoFrameCorrector stage(cfg, storage, probe);
    stage.begin_frame(header(W, H, 0));
    for (std::uint32_t r = 0; r < H; ++r) {
      ++pushed;
      stage.push_line(r, line);
      REQUIRE(probe.seen.size() == r + 1);  // out before the next line goes in
      CHECK(probe.seen.back().row == r);
    }
    stage.end_frame();
  }
  SECTION("bad-pixel stage") {
    fw::BadPixelConfig cfg;
    cfg.width = W;
    cfg.height = H;
    std::vector<fw::Pixel> storage(fw::BadPixelStage::storage_pixels(W, H));
    fw::BadPixelStage stage(cfg, storage, probe);
    stage.begin_frame(header(W, H, 0));
    for (std::uint32_t r = 0; r < H; ++r) {
      ++pushed;
      stage.push_line(r, line);
    }
    REQUIRE(probe.seen.size() == H - 1);
    for (std::uint32_t r = 0; r + 1 < H; ++r) {
      CHECK(probe.seen[r].row == r);
      CHECK(probe.seen[r].inputs_pushed == r + 1 + fw::BadPixelStage::kRadius);
    }
    stage.end_frame();
    REQUIRE(probe.seen.size() == H);
    CHECK(probe.seen.back().row == H - 1);
  }
}

TEST_CASE("the pipeline equals its stages applied one after another", "[pipeline]") {
  constexpr std::uint32_t W = 16, H = 12;
  SplitMix64 rng(7);
  std::vector<std::uint16_t> gain(W * H);
  std::vector<std::int16_t> offset(W * H);
  for (auto& g : gain) g = static_cast<std::uint16_t>(fw::kNucUnityGain - 800 + rng.below(1600));
  for (auto& o : offset) o = static_cast<std::int16_t>(static_cast<int>(rng.below(200)) - 100);
  std::vector<std::uint8_t> mask(W * H, 0);
  mask[3 * W + 5] = 1;
  mask[11 * W + 15] = 1;

  fw::PipelineConfig cfg;
  cfg.corrector.width = W;
  cfg.corrector.height = H;
  cfg.corrector.tau = {11'000'000, 13'000'000};
  cfg.use_nuc = true;
  cfg.nuc = {gain, offset};
  cfg.use_bad_pixels = true;
  cfg.bad_pixels.mask = mask;

  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(cfg));
  HashingCollector piped(W, H);
  fw::Pipeline pipeline(cfg, arena, piped);

  // The same stages, each run on whole frames into its own collector.
  std::vector<fw::Pixel> nuc_storage(W), bad_storage(fw::BadPixelStage::storage_pixels(W, H)),
      cor_storage(fw::TwoFrameCorrector::storage_pixels(W, H));
  HashingCollector after_nuc(W, H), after_bad(W, H), after_cor(W, H);
  fw::NucStage nuc(W, H, cfg.nuc, nuc_storage, after_nuc);
  fw::BadPixelConfig bad_cfg = cfg.bad_pixels;
  bad_cfg.width = W;
  bad_cfg.height = H;
  fw::BadPixelStage bad(bad_cfg, bad_storage, after_bad);
  fw::TwoFrameCorrector cor(cfg.corrector, cor_storage, after_cor);

  for (std::uint64_t f = 0; f < 6; ++f) {
    std::vector<fw::Pixel> frame(W * H);
    for (auto& v : frame) v = static_cast<fw::Pixel>(2000 + rng.below(12000));
    frame[7] = 0x3FFF;  // stuck high
    const auto hd = header(W, H, f);
    push_frame(pipeline.input(), hd, frame);
    push_frame(nuc, hd, frame);
    push_frame(bad, hd, after_nuc.frame());
    push_frame(cor, hd, after_bad.frame());
    REQUIRE(piped.frame() == after_cor.frame());
  }
  CHECK(pipeline.corrector().totals().by_reason[static_cast<int>(fw::CarryOver::applied)] == 5);
  CHECK(pipeline.bad_pixels()->last_frame().replaced == 2);
}

namespace {

// The bad-pixel rule written the plain way, on a whole frame of which only the first `rows`
// lines arrived: what the stage must emit for each of them.
std::vector<fw::Pixel> bad_pixel_reference(const std::vector<fw::Pixel>& frame, std::uint32_t w,
                                           std::uint32_t rows, const fw::BadPixelConfig& cfg,
                                           fw::BadPixelFrameStats& stats) {
  auto bad = [&](std::uint32_t r, std::uint32_t c) {
    const fw::Pixel v = frame[std::size_t{r} * w + c];
    const bool stuck = cfg.detect_stuck && (v == cfg.stuck_low || v == cfg.stuck_high);
    return stuck || (!cfg.mask.empty() && cfg.mask[std::size_t{r} * w + c] != 0);
  };
  std::vector<fw::Pixel> out(frame.begin(), frame.begin() + static_cast<std::ptrdiff_t>(rows) * w);
  for (std::uint32_t r = 0; r < rows; ++r)
    for (std::uint32_t c = 0; c < w; ++c) {
      if (!bad(r, c)) continue;
      std::uint32_t sum = 0, count = 0;
      for (std::uint32_t rr = r == 0 ? 0 : r - 1; rr <= std::min(r + 1, rows - 1); ++rr)
        for (std::uint32_t cc = c == 0 ? 0 : c - 1; cc <= std::min(c + 1, w - 1); ++cc)
          if (!bad(rr, cc)) {
            sum += frame[std::size_t{rr} * w + cc];
            ++count;
          }
      if (count == 0) {
        ++stats.unrepairable;
      } else {
        out[std::size_t{r} * w + c] = static_cast<fw::Pixel>((sum + count / 2) / count);
        ++stats.replaced;
      }
    }
  return out;
}

}  // namespace

TEST_CASE("the bad-pixel stage equals the plain rule on random frames", "[bad_pixel]") {
  SplitMix64 rng(23);
  // Widths past BadPixelStage::kRunPixels (smallest ring) and heights past the largest ring.
  for (std::uint32_t w : {1u, 2u, 3u, 31u, 32u, 33u, 64u, 65u, 100u, 160u, 2100u}) {
    for (std::uint32_t h : {1u, 2u, 3u, 4u, 7u, 70u}) {
      for (int variant = 0; variant < 12; ++variant) {
        // Densities from none to most pixels bad, with and without mask and stuck detection.
        const std::uint32_t per_mille = std::array<std::uint32_t, 6>{0, 1, 10, 100, 500, 950}[variant % 6];
        fw::BadPixelConfig cfg;
        cfg.width = w;
        cfg.height = h;
        cfg.detect_stuck = variant % 3 != 2;
        cfg.stuck_low = static_cast<fw::Pixel>(rng.below(3));
        cfg.stuck_high = static_cast<fw::Pixel>(0x3FFF - rng.below(2));
        std::vector<std::uint8_t> mask;
        if (variant % 4 != 3) {
          mask.resize(std::size_t{w} * h);
          for (auto& m : mask) m = rng.below(1000) < per_mille ? static_cast<std::uint8_t>(1 + rng.below(255)) : 0;
        }
        cfg.mask = mask;
        std::vector<fw::Pixel> frame(std::size_t{w} * h);
        for (auto& v : frame) {
          const std::uint32_t roll = rng.below(1000);
          v = roll < per_mille / 2         ? cfg.stuck_low
              : roll < per_mille           ? cfg.stuck_high
                                           : static_cast<fw::Pixel>(rng.below(0x4000));
        }
        std::vector<fw::Pixel> storage(fw::BadPixelStage::storage_pixels(w, h));
        HashingCollector sink(w, h);
        fw::BadPixelStage stage(cfg, storage, sink);
        INFO("w " << w << " h " << h << " variant " << variant);
        int pass = 0;
        for (std::uint32_t rows : {h, (h + 1) / 2, h, (h + 1) / 2}) {  // whole, cut short
          // Line by line, then as one run (push_lines' ring path).
          const bool as_run = ++pass > 2;
          sink.begin_frame(header(w, h, 0));
          stage.begin_frame(header(w, h, 0));
          if (as_run) {
            stage.push_lines(0, rows, frame.data(), w, w);
          } else {
            for (std::uint32_t r = 0; r < rows; ++r)
              stage.push_line(r, fw::LineView(frame.data() + std::size_t{r} * w, w));
          }
          stage.end_frame();
          fw::BadPixelFrameStats want_stats;
          const auto want = bad_pixel_reference(frame, w, rows, cfg, want_stats);
          CHECK(std::equal(want.begin(), want.end(), sink.frame().begin()));
          CHECK(sink.lines() == rows);
          CHECK(stage.last_frame().replaced == want_stats.replaced);
          CHECK(stage.last_frame().unrepairable == want_stats.unrepairable);
        }
        // Out of order after `k` lines: rows 0..k-1 come out as for a frame of k lines, the
        // offending line passes through unchanged.
        if (h >= 3) {
          const std::uint32_t k = h - 2;
          stage.begin_frame(header(w, h, 1));
          for (std::uint32_t r = 0; r < k; ++r)
            stage.push_line(r, fw::LineView(frame.data() + std::size_t{r} * w, w));
          stage.push_line(k + 1, fw::LineView(frame.data(), w));  // row k skipped
          fw::BadPixelFrameStats want_stats;
          const auto want = bad_pixel_reference(frame, w, k, cfg, want_stats);
          CHECK(std::equal(want.begin(), want.end(), sink.frame().begin()));
          CHECK(sink.last_row() == k + 1);
          CHECK(std::equal(frame.begin(), frame.begin() + w,
                           sink.frame().begin() + static_cast<std::ptrdiff_t>(k + 1) * w));
          CHECK(stage.last_frame().replaced == want_stats.replaced);
          CHECK(stage.last_frame().unrepairable == want_stats.unrepairable);
          stage.end_frame();
        }
      }
    }
  }
}

TEST_CASE("bad-pixel stage: rows beyond the frame's height are passed on, never read against the mask",
          "[bad_pixel]") {
  constexpr std::uint32_t W = 6, H = 3;
  std::vector<std::uint8_t> mask(W * H, 0);
  mask[4] = 1;
  fw::BadPixelConfig cfg;
  cfg.width = W;
  cfg.height = H;
  cfg.mask = mask;
  std::vector<fw::Pixel> storage(fw::BadPixelStage::storage_pixels(W, H));
  HashingCollector sink(W, H + 2);
  fw::BadPixelStage stage(cfg, storage, sink);
  std::vector<fw::Pixel> line(W, 700);
  stage.begin_frame(header(W, H, 0));
  for (std::uint32_t r = 0; r < H + 2; ++r) stage.push_line(r, line);  // two rows too many
  stage.end_frame();
  CHECK(sink.lines() == H + 2);  // every line delivered, none lost or invented
}
