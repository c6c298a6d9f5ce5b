#pragma once
// Per-pixel non-uniformity correction: out = sat_u16(round(in * gain / 2^14) + offset), with a
// Q2.14 gain and a signed offset in counts per pixel. Tables belong to the caller.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/firmware/stage.hpp"

namespace bolo::fw {

inline constexpr unsigned kNucGainFractionBits = 14;
inline constexpr std::uint16_t kNucUnityGain = 1u << kNucGainFractionBits;

struct NucTables {
  std::span<const std::uint16_t> gain_q14;  // width * height, row-major
  std::span<const std::int16_t> offset;     // width * height, row-major
};

void nuc_line(const Pixel* in, const std::uint16_t* gain_q14, const std::int16_t* offset,
              Pixel* out, std::size_t width);

class NucStage final : public Stage {
 public:
  static constexpr std::size_t storage_pixels(std::uint32_t width) { return width; }
  NucStage(std::uint32_t width, std::uint32_t height, NucTables tables, std::span<Pixel> storage,
           LineSink& next);

  void begin_frame(const FrameHeader& header) override;
  void push_line(std::uint32_t row, LineView line) override;
  void end_frame() override;

 private:
  std::uint32_t width_, height_;
  NucTables tables_;
  std::span<Pixel> out_line_;
  bool active_ = false;  // this frame has the configured size
};

}  // namespace bolo::fw
