#pragma once
// Bad-pixel replacement over a 3x3 neighbourhood: a pixel marked bad (static mask from the
// source) or stuck (reads exactly the low or high rail) is replaced by the rounded mean of its
// good neighbours. Holds three input lines in a ring, so row r leaves when row r+1 arrives.
// Rows are handed on straight from the ring, repaired in place, without a copy.
// Optionally the stage applies a NUC to each input line on its way into the ring: the output is
// that of NucStage -> BadPixelStage, in one pass over the line instead of two (Pipeline uses it
// when both stages are enabled).

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/firmware/nuc_stage.hpp"
#include "bolo/firmware/stage.hpp"

namespace bolo::fw {

struct BadPixelConfig {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::span<const std::uint8_t> mask;  // width * height, non-zero = bad; may be empty
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
  // Three input lines, one line for the input NUC of lines passed through, and the three lines'
  // bad flags as bits (32-bit words, two pixels of room each).
  static constexpr std::size_t flag_words(std::uint32_t width) { return (std::size_t{width} + 31) / 32; }
  static constexpr std::size_t storage_pixels(std::uint32_t width) {
    return std::size_t{width} * 4 + 3 * 2 * flag_words(width);
  }
  BadPixelStage(const BadPixelConfig& config, std::span<Pixel> storage, LineSink& next);
  // With NUC on input. Tables shorter than a frame are a configuration bug: the stage then
  // passes every frame through untouched, as a misconfigured NucStage and BadPixelStage do.
  BadPixelStage(const BadPixelConfig& config, const NucTables& input_nuc,
                std::span<Pixel> storage, LineSink& next);

  void begin_frame(const FrameHeader& header) override;
  void push_line(std::uint32_t row, LineView line) override;
  void end_frame() override;

  const BadPixelFrameStats& last_frame() const { return stats_; }

 private:
  Pixel* ring_line(std::uint32_t row) { return ring_.data() + std::size_t{row % 3} * width_; }
  // Row's flag bits: 32-bit words in native byte order, read and written with memcpy.
  std::uint8_t* ring_flags(std::uint32_t row) {
    return flags_.data() + std::size_t{row % 3} * flag_words(width_) * 4;
  }
  void emit(std::uint32_t row);
  // Replaces flagged pixel x of `row` by the rounded mean of its good 3x3 neighbours.
  [[gnu::noinline]] void repair(std::uint32_t row, std::uint32_t x);
  void pass_through(std::uint32_t row, LineView line);

  BadPixelConfig config_;
  std::uint32_t width_, height_;
  std::span<Pixel> ring_, out_line_;
  std::span<std::uint8_t> flags_;
  const NucTables* nuc_ = nullptr;  // &nuc_tables_ when NUC is applied on input
  NucTables nuc_tables_;
  bool nuc_frame_ = false;  // this frame gets the NUC (its size is the configured one)
  std::uint32_t rows_in_ = 0;
  bool row_flagged_[3] = {};  // whether each ring line has a flagged pixel
  bool active_ = false;
  BadPixelFrameStats stats_{};
};

}  // namespace bolo::fw
