#pragma once
// A V4L2 (UVC) frame buffer as the driver hands it over: `image_rows` rows of pixels, then, for
// Y16 only, `telemetry_rows` rows of Lepton telemetry (PureThermal's 160x122: 120 image rows + 2;
// 80x63: 60 + 3; row A is the first 80 words of the first telemetry row), each row
// `bytes_per_line` apart (drivers may pad). Y16 pixels are the core's 16-bit counts (little
// endian); GREY, YUYV and UYVY are the camera's 8-bit tone-mapped video, of which the luma is
// taken. Pure: no I/O, no allocation (board-safe).

#include <cstdint>
#include <span>

#include "bolo/hal/lepton_telemetry.hpp"

namespace bolo::hal {

enum class V4l2Pixels : std::uint8_t { y16, grey, yuyv, uyvy };

// Bytes per pixel in a row: 2 for Y16 and the 4:2:2 modes (Y U Y V: a Y byte per pixel), 1 for GREY.
std::uint32_t bytes_per_pixel(V4l2Pixels pixels);
// The 8-bit modes: display video after the camera's AGC, never radiometric counts.
inline bool tone_mapped(V4l2Pixels pixels) { return pixels != V4l2Pixels::y16; }

struct Y16Layout {
  std::uint32_t width = 0;
  std::uint32_t image_rows = 0;
  std::uint32_t telemetry_rows = 0;
  std::uint32_t bytes_per_line = 0;  // 0 = width * bytes_per_pixel
  V4l2Pixels pixels = V4l2Pixels::y16;
  std::uint32_t stride() const { return bytes_per_line != 0 ? bytes_per_line : row_bytes(); }
  std::uint32_t row_bytes() const { return width * bytes_per_pixel(pixels); }
  std::uint64_t min_bytes() const;   // what a whole frame needs (the last row unpadded)
  bool valid() const;                // width > 0, rows > 0, stride holds a row, telemetry only in Y16
};

enum class Y16Check : std::uint8_t { ok, bad_layout, short_frame };

class Y16Frame {
 public:
  // Checks `bytes` against `layout`; the frame reads nothing outside `bytes`.
  static Y16Check check(std::span<const std::uint8_t> bytes, const Y16Layout& layout);
  Y16Frame(std::span<const std::uint8_t> bytes, const Y16Layout& layout) : bytes_(bytes), layout_(layout) {}

  // Image row `row` into `out` (at least width words): Y16 counts, or the 8-bit luma (0..255).
  // Only after check() == ok.
  void image_row(std::uint32_t row, std::span<std::uint16_t> out) const;
  // Decodes telemetry row A; false when the layout has no telemetry rows or they are too narrow.
  bool telemetry(LeptonTelemetry& out) const;

 private:
  std::uint16_t word(std::uint32_t row, std::uint32_t x) const;
  std::span<const std::uint8_t> bytes_;
  Y16Layout layout_;
};

}  // namespace bolo::hal
