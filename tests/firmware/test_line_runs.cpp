// push_lines is defined as the same number of push_line calls in order. The corrector (and the
// pipeline that ends in it) take a faster path for runs, so these tests feed the same streams to
// one instance line by line and to another in runs of random lengths and strides, well-formed and
// broken, and require identical output events, pixels and statistics.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "bolo/firmware/bad_pixel_stage.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::SplitMix64;

namespace {

// Hashes every event: frame boundaries, row numbers, line widths and pixels, in order. Takes
// runs through the default push_lines, i.e. as single lines.
class EventHash final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& h) override { mix(0xB0 ^ h.sequence); }
  void push_line(std::uint32_t row, fw::LineView line) override {
    mix(0x11);
    mix(row);
    mix(line.size());
    for (fw::Pixel p : line) mix(p);
    ++lines_;
  }
  void end_frame() override { mix(0xE0); }
  std::uint64_t hash() const { return hash_; }
  std::uint64_t lines() const { return lines_; }

 private:
  void mix(std::uint64_t v) {
    hash_ ^= v;
    hash_ *= 0x100000001b3ull;
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
  std::uint64_t lines_ = 0;
};

// One push of a source: rows first..first+count-1, `width` pixels each, `stride` apart.
struct Run {
  std::uint32_t first, count, width;
  std::size_t stride;
};

// A frame's pushes: kind 0 is well-formed, the others break it the ways a source can (kind 6
// adds an empty run: a bad-pixel stage once read past the input on one, found by fuzz_pipeline).
std::vector<Run> schedule(int kind, std::uint32_t w, std::uint32_t h, SplitMix64& rng) {
  std::vector<Run> rows;  // one row each, grouped into runs below
  for (std::uint32_t r = 0; r < h; ++r) rows.push_back({r, 1, w, w});
  switch (kind) {
    case 1: rows.resize(rng.below(h) + 1); break;                            // cut short
    case 2: if (h > 2) rows.erase(rows.begin() + rng.below(h - 1) + 1); break;  // a row skipped
    case 3: rows.insert(rows.begin() + rng.below(h), {0, 1, w, w}); break;     // a row repeated
    case 4: rows[rng.below(h)].width = w > 1 ? w - 1 : w + 1; break;           // a short line
    case 5: rows.push_back({h, 1, w, w}); rows.push_back({h + 1, 1, w, w}); break;  // past the end
    default: break;
  }
  // Group consecutive rows of equal width into runs of random length; some with padding.
  std::vector<Run> runs;
  const std::size_t pad = rng.below(3) == 0 ? rng.below(5) + 1 : 0;
  const bool longest = rng.below(3) == 0;  // whole frames in one run: several chunks per run
  for (const Run& r : rows) {
    if (!runs.empty() && (longest || rng.below(4) != 0)) {
      Run& last = runs.back();
      if (last.first + last.count == r.first && last.width == r.width) {
        ++last.count;
        continue;
      }
    }
    runs.push_back({r.first, 1, r.width, std::size_t{r.width} + pad});
  }
  if (kind == 6) {  // an empty run, in order (where the next row is due): nothing happens
    const std::size_t at = rng.below(static_cast<std::uint32_t>(runs.size()) + 1);
    runs.insert(runs.begin() + static_cast<std::ptrdiff_t>(at), {at < runs.size() ? runs[at].first : h, 0, w, w});
  }
  return runs;
}

fw::FrameHeader header(std::uint32_t w, std::uint32_t h, std::uint64_t seq) {
  fw::FrameHeader hd;
  hd.width = w;
  hd.height = h;
  hd.sequence = seq;
  hd.sequence_valid = true;
  hd.timestamp_ns = static_cast<std::int64_t>(seq) * 16'666'667;
  hd.timestamp_valid = true;
  hd.exposure_ns = 10'000'000;
  hd.readout_ns = 6'000'000;
  return hd;
}

// Plays a frame's runs into two sinks: `lines` gets push_line calls, `runs` push_lines calls.
void play(fw::LineSink& lines, fw::LineSink& runs, const fw::FrameHeader& hd,
          const std::vector<Run>& schedule, std::vector<fw::Pixel>& buffer, SplitMix64& rng) {
  lines.begin_frame(hd);
  runs.begin_frame(hd);
  for (const Run& r : schedule) {
    const std::size_t need = r.count == 0 ? 0 : (r.count - 1) * r.stride + r.width;
    buffer.resize(need);
    // Mostly mid-range values; some anywhere (saturation counts), some on the stuck rails.
    for (fw::Pixel& p : buffer) {
      const std::uint32_t pick = rng.below(40);
      p = static_cast<fw::Pixel>(pick == 0   ? 0x3FFF
                                 : pick == 1 ? 0
                                 : pick < 6  ? rng.below(65536)
                                             : 8000 + rng.below(2000));
    }
    for (std::uint32_t i = 0; i < r.count; ++i)
      lines.push_line(r.first + i, fw::LineView(buffer.data() + i * r.stride, r.width));
    runs.push_lines(r.first, r.count, buffer.data(), r.width, r.stride);
  }
  lines.end_frame();
  runs.end_frame();
}

void require_same(const fw::TwoFrameCorrector& a, const fw::TwoFrameCorrector& b) {
  const fw::CorrectorFrameStats& x = a.last_frame();
  const fw::CorrectorFrameStats& y = b.last_frame();
  REQUIRE(x.carry_over == y.carry_over);
  REQUIRE(x.saturated_low == y.saturated_low);
  REQUIRE(x.saturated_high == y.saturated_high);
  REQUIRE(x.rows_uncorrected == y.rows_uncorrected);
  REQUIRE(a.totals().frames == b.totals().frames);
  for (std::size_t i = 0; i < fw::kCarryOverReasons; ++i)
    REQUIRE(a.totals().by_reason[i] == b.totals().by_reason[i]);
}

}  // namespace

TEST_CASE("corrector: runs give what single lines give, broken frames included", "[corrector][runs]") {
  SplitMix64 rng(2026);
  // Widths below, at and above the run chunk (TwoFrameCorrector::kRunPixels pixels).
  const std::uint32_t sizes[][2] = {{8, 4}, {37, 5}, {160, 60}, {640, 9}, {4097, 3}, {1, 1}};
  for (const auto& size : sizes) {
    const std::uint32_t w = size[0], h = size[1];
    fw::CorrectorConfig cfg;
    cfg.width = w;
    cfg.height = h;
    cfg.tau = {11'000'000, 13'000'000};
    std::vector<fw::Pixel> store_a(fw::TwoFrameCorrector::storage_pixels(w, h));
    std::vector<fw::Pixel> store_b(store_a.size());
    EventHash out_a, out_b;
    fw::TwoFrameCorrector a(cfg, store_a, out_a), b(cfg, store_b, out_b);
    std::vector<fw::Pixel> buffer;
    std::uint64_t seq = 0;
    for (int frame = 0; frame < 60; ++frame) {
      const int kind = rng.below(3) == 0 ? static_cast<int>(rng.below(7)) : 0;
      seq += rng.below(10) == 0 ? 2 : 1;  // an occasional sequence gap
      play(a, b, header(w, h, seq), schedule(kind, w, h, rng), buffer, rng);
      INFO("size " << w << "x" << h << " frame " << frame << " kind " << kind);
      REQUIRE(out_a.hash() == out_b.hash());
      REQUIRE(out_a.lines() == out_b.lines());
      require_same(a, b);
      // The frame stores (the next frame's predecessor); the output rows after them differ.
      REQUIRE(std::equal(store_a.begin(), store_a.begin() + static_cast<std::ptrdiff_t>(w) * h, store_b.begin()));
    }
  }
}

TEST_CASE("pipeline: runs give what single lines give, broken frames included", "[pipeline][runs]") {
  SplitMix64 rng(7);
  // Ring sizes (BadPixelStage::ring_rows) from 64 lines down to 4, frames higher and lower.
  for (std::uint32_t w : {1u, 16u, 33u, 160u, 700u, 5000u}) {
    const std::uint32_t h = w == 16 ? 70 : 30;
    const std::size_t n = std::size_t{w} * h;
    std::vector<std::uint16_t> gain(n);
    std::vector<std::int16_t> offset(n);
    std::vector<std::uint8_t> mask(n);
    for (std::size_t i = 0; i < n; ++i) {
      gain[i] = static_cast<std::uint16_t>(16384 - 500 + rng.below(1000));
      offset[i] = static_cast<std::int16_t>(static_cast<int>(rng.below(400)) - 200);
      mask[i] = rng.below(50) == 0 ? 1 : 0;
    }
    fw::PipelineConfig cfg;
    cfg.corrector.width = w;
    cfg.corrector.height = h;
    cfg.corrector.tau = {11'000'000, 13'000'000};
    cfg.use_nuc = true;
    cfg.nuc.gain_q14 = gain;
    cfg.nuc.offset = offset;
    cfg.use_bad_pixels = true;
    cfg.bad_pixels.mask = mask;
    cfg.bad_pixels.detect_stuck = true;
    std::vector<fw::Pixel> arena_a(fw::Pipeline::arena_pixels(cfg)), arena_b(arena_a.size());
    EventHash out_a, out_b;
    fw::Pipeline a(cfg, arena_a, out_a), b(cfg, arena_b, out_b);
    std::vector<fw::Pixel> buffer;
    for (std::uint64_t seq = 1; seq <= 40; ++seq) {
      const int kind = rng.below(3) == 0 ? static_cast<int>(rng.below(7)) : 0;
      play(a.input(), b.input(), header(w, h, seq), schedule(kind, w, h, rng), buffer, rng);
      INFO("width " << w << " frame " << seq << " kind " << kind);
      REQUIRE(out_a.hash() == out_b.hash());
      require_same(a.corrector(), b.corrector());
      REQUIRE(a.bad_pixels()->last_frame().replaced == b.bad_pixels()->last_frame().replaced);
      REQUIRE(a.bad_pixels()->last_frame().unrepairable ==
              b.bad_pixels()->last_frame().unrepairable);
    }
  }
}

TEST_CASE("bad-pixel ring: a power of two, room for a row and both its neighbours", "[bad_pixel][runs]") {
  for (std::uint32_t w : {0u, 1u, 2u, 100u, 160u, 640u, 1024u, 2047u, 2048u, 2049u, 5000u,
                          1u << 20, 0xFFFFFFFFu}) {
    const std::uint32_t rows = fw::BadPixelStage::ring_rows(w);
    INFO("width " << w);
    REQUIRE(rows >= 4);
    REQUIRE(rows <= 64);
    REQUIRE((rows & (rows - 1)) == 0);
  }
}
