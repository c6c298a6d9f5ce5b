#pragma once
// Small raster helpers for `bolo render`: value -> colour maps, an RGB canvas, frames drawn with
// a fixed display range and nearest-neighbour upscaling, and 3x5 digit labels (no fonts).

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace bolo::cli {

enum class Colormap { gray, iron };
// Throws bolo::cli::Error naming --colormap for an unknown name.
Colormap parse_colormap(const std::string& name);

using Rgb = std::array<std::uint8_t, 3>;
// t in [0, 1] (clamped; NaN -> 0).
Rgb map_colour(Colormap map, double t);

struct DisplayRange {
  double lo = 0, hi = 1;
};

// `p_lo`, `p_hi` in [0, 100]: linearly interpolated percentiles of `values` (reordered).
DisplayRange percentile_range(std::vector<float>& values, double p_lo, double p_hi);

class Canvas {
 public:
  Canvas(std::uint32_t width, std::uint32_t height, Rgb background);
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  const std::vector<std::uint8_t>& rgb() const { return rgb_; }

  void fill(std::uint32_t x, std::uint32_t y, std::uint32_t w, std::uint32_t h, Rgb colour);
  // Draws a (frame_w x frame_h) frame at (x, y), each pixel as a scale x scale block.
  void draw_frame(std::uint32_t x, std::uint32_t y, std::span<const float> frame,
                  std::uint32_t frame_w, std::uint32_t frame_h, DisplayRange range,
                  Colormap map, std::uint32_t scale);
  // Digits only (other characters are skipped), 3x5 glyphs of `dot` pixels, white on black.
  void draw_number(std::uint32_t x, std::uint32_t y, const std::string& digits, std::uint32_t dot);

 private:
  void set(std::uint32_t x, std::uint32_t y, Rgb colour);
  std::uint32_t width_, height_;
  std::vector<std::uint8_t> rgb_;
};

}  // namespace bolo::cli
