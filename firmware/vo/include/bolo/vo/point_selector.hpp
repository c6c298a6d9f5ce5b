#pragma once
// Region-adaptive, gradient-based point selection: the image is cut into blocks; a pixel is a
// candidate when its gradient magnitude exceeds its block's median plus a margin, and each cell
// of a grid keeps its strongest candidate. Cells grow or shrink until about the wanted number of
// points is found, so textured and flat regions both contribute.

#include <cstdint>
#include <span>

#include "bolo/vo/image.hpp"

namespace bolo::vo {

struct PixelPoint {
  std::uint16_t x = 0, y = 0;
  float gradient = 0;  // magnitude
};

struct SelectorScratch {
  std::span<float> block_threshold;   // one per 16x16 block
  std::span<std::uint16_t> histogram;  // 64 bins
};
std::size_t selector_block_count(std::uint32_t width, std::uint32_t height);

// Selects up to out.size() points from level 0 of `level`, skipping pixels where `occupied`
// (width x height, may be empty) is non-zero and a border of `margin` pixels. Returns the count.
// `intensity_scale` scales the gradient histogram's bins and the margin (VoConfig).
std::size_t select_points(const Level& level, std::span<const std::uint8_t> occupied,
                          std::uint32_t wanted, std::uint32_t margin, SelectorScratch scratch,
                          std::span<PixelPoint> out, float intensity_scale = 1.0f);

}  // namespace bolo::vo
