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

// One pixel of the NUC: the definition nuc_line applies to every pixel.
inline Pixel nuc_pixel(Pixel in, std::uint16_t gain_q14, std::int16_t offset) {
  constexpr std::int32_t kNucHalf = 1 << (kNucGainFractionBits - 1);
  // in * gain + half < 2^32: no overflow in 32 bits; values are non-negative so +half then shift
  // rounds to nearest with ties away from zero.
  const std::int32_t scaled =
      static_cast<std::int32_t>((std::uint32_t{in} * gain_q14 + kNucHalf) >> kNucGainFractionBits);
  const std::int32_t value = scaled + offset;
  return static_cast<Pixel>(value < 0 ? 0 : (value > 0xFFFF ? 0xFFFF : value));
}

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
