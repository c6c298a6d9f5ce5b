#pragma once
// Bad-pixel replacement over a 3x3 neighbourhood: a pixel marked bad (static mask from the
// source) or stuck (reads exactly the low or high rail) is replaced by the rounded mean of its
// good neighbours. Holds input lines in a ring (three would do; more let push_lines hand rows on
// in runs), and row r leaves when row r+1 arrives.
// Rows are handed on straight from the ring, repaired in place, without a copy.
// Optionally the stage applies a NUC to each input line on its way into the ring: the output is
// that of NucStage -> BadPixelStage, in one pass over the line instead of two (Pipeline uses it
// when both stages are enabled).

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/firmware/nuc_stage.hpp"
#include "bolo/firmware/stage.hpp"

namespace bolo::fw {

namespace detail {
struct IngestLine;
}  // namespace detail

struct BadPixelConfig {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  // width * height, non-zero = bad; may be empty. Read once, at construction (the stage keeps it
  // as bits in its storage), so it need not outlive the stage.
  std::span<const std::uint8_t> mask;
  bool detect_stuck = true;
  Pixel stuck_low = 0;
  Pixel stuck_high = 0x3FFF;  // 14-bit rail by default
};

struct BadPixelFrameStats {
  std::uint32_t replaced = 0;
  std::uint32_t unrepairable = 0;  // bad pixels with no good neighbour: passed through
};

class BadPixelStage final : public Stage {
 public:
  static constexpr std::uint32_t kRadius = 1;
  // Ring lines: room for about kRunPixels pixels of rows that leave as one run plus the two
  // neighbours a repair needs, rounded up to a power of two (the slot is a mask, not a divide),
  // at least 4 and at most 64 (the row_flagged_ bits).
  static constexpr std::size_t kRunPixels = 2048;
  // Frames of at least this many pixels have their input and NUC tables prefetched ahead by the
  // intake (IngestLine::prefetch): it pays where tables and input come from L3 or DRAM, not at
  // the sizes that sit in L2.
  static constexpr std::size_t kPrefetchFromPixels = std::size_t{1} << 20;
  static constexpr std::uint32_t ring_rows(std::uint32_t width) {
    const std::size_t run = width == 0 || width > kRunPixels ? 1 : kRunPixels / width;
    const std::size_t rows = std::bit_ceil(run + 2);
    return static_cast<std::uint32_t>(rows > 64 ? 64 : rows);
  }
  // The ring lines, one line for the input NUC of lines passed through, the ring lines' bad
  // flags as bits (32-bit words, two pixels of room each), and the mask as bits in the same
  // layout, one row of words per frame row (the intake reads a bit per pixel, not a byte).
  static constexpr std::size_t flag_words(std::uint32_t width) { return (std::size_t{width} + 31) / 32; }
  static constexpr std::size_t storage_pixels(std::uint32_t width, std::uint32_t height) {
    return std::size_t{width} * (ring_rows(width) + 1) +
           (std::size_t{ring_rows(width)} + height) * 2 * flag_words(width);
  }
  BadPixelStage(const BadPixelConfig& config, std::span<Pixel> storage, LineSink& next);
  // With NUC on input. Tables shorter than a frame are a configuration bug: the stage then
  // passes every frame through untouched, as a misconfigured NucStage and BadPixelStage do.
  BadPixelStage(const BadPixelConfig& config, const NucTables& input_nuc,
                std::span<Pixel> storage, LineSink& next);

  void begin_frame(const FrameHeader& header) override;
  void push_line(std::uint32_t row, LineView line) override;
  // In-order rows of a good frame are taken into the ring and leave, repaired, as runs of
  // consecutive ring lines; anything else line by line.
  void push_lines(std::uint32_t first_row, std::uint32_t count, const Pixel* pixels,
                  std::size_t width, std::size_t stride) override;
  void end_frame() override;

  const BadPixelFrameStats& last_frame() const { return stats_; }

 private:
  Pixel* ring_line(std::uint32_t row) {
    return ring_.data() + std::size_t{row & (ring_rows_ - 1)} * width_;
  }
  // Row's flag bits: 32-bit words in native byte order, read and written with memcpy.
  std::uint8_t* ring_flags(std::uint32_t row) {
    return flags_.data() + std::size_t{row & (ring_rows_ - 1)} * flag_words(width_) * 4;
  }
  // Row `row`'s intake: its input, mask, NUC tables, ring line and flags.
  detail::IngestLine ingest_job(std::uint32_t row, const Pixel* input);
  void ingest(std::uint32_t row, const Pixel* line);
  void ingest_run(std::uint32_t row, std::uint32_t count, const Pixel* lines, std::size_t stride);
  void repair_row(std::uint32_t row);
  void repair_rows(std::uint32_t first, std::uint32_t count);
  void repair_flagged_row(std::uint32_t row);
  void emit(std::uint32_t row);
  // Replaces flagged pixel x of `row` by the rounded mean of its good 3x3 neighbours.
  [[gnu::noinline]] void repair(std::uint32_t row, std::uint32_t x);
  void pass_through(std::uint32_t row, LineView line);

  BadPixelConfig config_;
  std::uint32_t width_, height_;
  std::uint32_t ring_rows_ = 4;
  std::span<Pixel> ring_, out_line_;
  std::span<std::uint8_t> flags_;
  const std::uint8_t* mask_bits_ = nullptr;  // in the storage; nullptr: no mask
  const NucTables* nuc_ = nullptr;  // &nuc_tables_ when NUC is applied on input
  NucTables nuc_tables_;
  bool nuc_frame_ = false;  // this frame gets the NUC (its size is the configured one)
  std::uint32_t rows_in_ = 0;
  std::uint64_t row_flagged_ = 0;  // bit i: ring line i has a flagged pixel
  bool active_ = false;
  BadPixelFrameStats stats_{};
};

}  // namespace bolo::fw
