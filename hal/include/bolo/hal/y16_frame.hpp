#pragma once
// A Y16 frame buffer as a V4L2 (UVC) driver hands it over: `image_rows` rows of little-endian
// uint16 pixels, then `telemetry_rows` rows of Lepton telemetry (PureThermal's 160x122 format:
// 120 image rows + 2 telemetry rows; row A is the first 80 words of the first telemetry row),
// each row `bytes_per_line` apart (drivers may pad). Pure: no I/O, no allocation (board-safe).

#include <cstdint>
#include <span>

#include "bolo/hal/lepton_telemetry.hpp"

namespace bolo::hal {

struct Y16Layout {
  std::uint32_t width = 0;
  std::uint32_t image_rows = 0;
  std::uint32_t telemetry_rows = 0;
  std::uint32_t bytes_per_line = 0;  // 0 = width * 2
  std::uint32_t stride() const { return bytes_per_line != 0 ? bytes_per_line : width * 2; }
  std::uint64_t min_bytes() const;   // what a whole frame needs (the last row unpadded)
  bool valid() const;                // width > 0, rows > 0, stride holds a row
};

enum class Y16Check : std::uint8_t { ok, bad_layout, short_frame };

class Y16Frame {
 public:
  // Checks `bytes` against `layout`; the frame reads nothing outside `bytes`.
  static Y16Check check(std::span<const std::uint8_t> bytes, const Y16Layout& layout);
  Y16Frame(std::span<const std::uint8_t> bytes, const Y16Layout& layout) : bytes_(bytes), layout_(layout) {}

  // Image row `row` into `out` (at least width words). Only after check() == ok.
  void image_row(std::uint32_t row, std::span<std::uint16_t> out) const;
  // Decodes telemetry row A; false when the layout has no telemetry rows or they are too narrow.
  bool telemetry(LeptonTelemetry& out) const;

 private:
  std::uint16_t word(std::uint32_t row, std::uint32_t x) const;
  std::span<const std::uint8_t> bytes_;
  Y16Layout layout_;
};

}  // namespace bolo::hal
