// The bad-pixel stage with NUC on its input must be NucStage -> BadPixelStage, line for line:
// same pixels, same rows, same order, same statistics, for well-formed and broken frames.

#include <catch2/catch.hpp>

#include <array>
#include <vector>

#include "bolo/firmware/bad_pixel_stage.hpp"
#include "bolo/firmware/nuc_stage.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::HashingCollector;
using bolo::test::SplitMix64;

namespace {

// What a source does to a frame: the header it announces and the rows (and widths) it pushes.
struct Push {
  std::uint32_t row, width;
};

std::vector<Push> schedule(int kind, std::uint32_t w, std::uint32_t h, SplitMix64& rng) {
  std::vector<Push> pushes;
  for (std::uint32_t r = 0; r < h; ++r) pushes.push_back({r, w});
  switch (kind) {
    case 0: break;                                                     // well-formed
    case 1: pushes.resize(rng.below(h) + 1); break;                    // cut short
    case 2: if (h > 2) pushes.erase(pushes.begin() + 1); break;        // a row skipped
    case 3: pushes.insert(pushes.begin() + rng.below(h), {0, w}); break;  // a row repeated
    case 4: pushes[rng.below(h)].width = w > 1 ? w - 1 : w + 1; break;    // a short line
    case 5: pushes.push_back({h, w}); pushes.push_back({h + 1, w}); break;  // rows past the end
    default: break;
  }
  return pushes;
}

void play(fw::LineSink& sink, const fw::FrameHeader& hd, const std::vector<Push>& pushes,
          const std::vector<fw::Pixel>& frame, std::uint32_t w) {
  sink.begin_frame(hd);
  for (const Push& p : pushes) {
    const std::size_t at = std::size_t{p.row % hd.height} * w;  // rows past the end reuse data
    sink.push_line(p.row, fw::LineView(frame.data() + at, p.width));
  }
  sink.end_frame();
}

}  // namespace

TEST_CASE("bad-pixel stage with NUC on input equals NucStage -> BadPixelStage", "[bad_pixel][nuc]") {
  SplitMix64 rng(31);
  for (std::uint32_t w : {1u, 3u, 17u, 32u, 33u, 160u}) {
    for (std::uint32_t h : {1u, 2u, 3u, 6u}) {
      const std::size_t n = std::size_t{w} * h;
      std::vector<std::uint16_t> gain(n);
      std::vector<std::int16_t> offset(n);
      std::vector<std::uint8_t> mask(n);
      for (int variant = 0; variant < 8; ++variant) {
        for (std::size_t i = 0; i < n; ++i) {
          // Mostly near unity with small offsets (so raw rails stay rails), some extreme.
          const bool extreme = rng.below(8) == 0;
          gain[i] = extreme ? static_cast<std::uint16_t>(rng.next())
                            : static_cast<std::uint16_t>(fw::kNucUnityGain - 300 + rng.below(600));
          offset[i] = extreme ? static_cast<std::int16_t>(rng.next())
                              : static_cast<std::int16_t>(static_cast<int>(rng.below(9)) - 4);
          if (variant % 2 == 0 && !extreme) {
            gain[i] = fw::kNucUnityGain;
            offset[i] = 0;
          }
          mask[i] = rng.below(20) == 0 ? 1 : 0;
        }
        fw::BadPixelConfig cfg;
        cfg.width = w;
        cfg.height = h;
        cfg.detect_stuck = variant % 4 != 3;
        if (variant % 4 != 2) cfg.mask = mask;
        const fw::NucTables tables{gain, offset};

        std::vector<fw::Pixel> nuc_storage(fw::NucStage::storage_pixels(w));
        std::vector<fw::Pixel> bad_storage(fw::BadPixelStage::storage_pixels(w, h));
        std::vector<fw::Pixel> fused_storage(fw::BadPixelStage::storage_pixels(w, h));
        HashingCollector chained(w, h + 2), fused(w, h + 2);
        fw::BadPixelStage bad(cfg, bad_storage, chained);
        fw::NucStage nuc(w, h, tables, nuc_storage, bad);
        fw::BadPixelStage both(cfg, tables, fused_storage, fused);

        for (int kind = 0; kind < 7; ++kind) {
          std::vector<fw::Pixel> frame(n);
          for (auto& v : frame) {
            const std::uint32_t roll = rng.below(40);
            v = roll == 0 ? 0 : roll == 1 ? 0x3FFF : static_cast<fw::Pixel>(rng.below(0x4000));
          }
          fw::FrameHeader hd;
          hd.width = w;
          hd.height = kind == 6 ? h + 1 : h;  // kind 6: a frame of another size
          const auto pushes = schedule(kind, w, h, rng);
          play(nuc, hd, pushes, frame, w);
          play(both, hd, pushes, frame, w);
          INFO("w " << w << " h " << h << " variant " << variant << " kind " << kind);
          CHECK(fused.hash() == chained.hash());
          CHECK(fused.lines() == chained.lines());
          CHECK(fused.last_row() == chained.last_row());
          CHECK(both.last_frame().replaced == bad.last_frame().replaced);
          CHECK(both.last_frame().unrepairable == bad.last_frame().unrepairable);
        }
      }
    }
  }
}

TEST_CASE("bad-pixel stage with NUC tables shorter than a frame passes frames through",
          "[bad_pixel][nuc]") {
  constexpr std::uint32_t W = 4, H = 2;
  std::vector<std::uint16_t> gain(W * H - 1, 2 * fw::kNucUnityGain);
  std::vector<std::int16_t> offset(W * H, 0);
  std::vector<fw::Pixel> storage(fw::BadPixelStage::storage_pixels(W, H));
  HashingCollector sink(W, H);
  fw::BadPixelConfig cfg;
  cfg.width = W;
  cfg.height = H;
  fw::BadPixelStage stage(cfg, fw::NucTables{gain, offset}, storage, sink);
  const std::vector<fw::Pixel> frame = {5, 6, 0x3FFF, 8, 9, 10, 11, 12};
  fw::FrameHeader hd;
  hd.width = W;
  hd.height = H;
  bolo::test::push_frame(stage, hd, frame);
  CHECK(sink.frame() == frame);
}
