#include "bolo/vo/point_selector.hpp"

#include <cmath>

namespace bolo::vo {

namespace {
constexpr std::uint32_t kBlock = 16;
constexpr std::uint32_t kBins = 64;
constexpr float kBinWidth = 4.0f;  // gradient magnitude per histogram bin (counts / pixel)
constexpr float kMarginCounts = 6.0f;  // a candidate's gradient over its block's median

float magnitude(const Level& level, std::size_t i) {
  return std::sqrt(level.gx.data[i] * level.gx.data[i] + level.gy.data[i] * level.gy.data[i]);
}
}  // namespace

std::size_t selector_block_count(std::uint32_t width, std::uint32_t height) {
  return std::size_t{(width + kBlock - 1) / kBlock} * ((height + kBlock - 1) / kBlock);
}

std::size_t select_points(const Level& level, std::span<const std::uint8_t> occupied,
                          std::uint32_t wanted, std::uint32_t margin, SelectorScratch scratch,
                          std::span<PixelPoint> out, float intensity_scale) {
  // A multiplication per pixel, not a division (at scale 1 the same 0.25 the constant gave).
  const float bin_width = kBinWidth * intensity_scale, per_bin = 1.0f / bin_width;
  const float margin_counts = kMarginCounts * intensity_scale;
  const std::uint32_t w = level.value.width, h = level.value.height;
  const std::uint32_t bw = (w + kBlock - 1) / kBlock, bh = (h + kBlock - 1) / kBlock;
  // Per block: median gradient (from a histogram) plus a margin, so a point must stand out
  // against its own surroundings rather than against the whole image.
  for (std::uint32_t by = 0; by < bh; ++by)
    for (std::uint32_t bx = 0; bx < bw; ++bx) {
      for (std::uint32_t b = 0; b < kBins; ++b) scratch.histogram[b] = 0;
      std::uint32_t n = 0;
      for (std::uint32_t y = by * kBlock; y < h && y < (by + 1) * kBlock; ++y)
        for (std::uint32_t x = bx * kBlock; x < w && x < (bx + 1) * kBlock; ++x) {
          const auto bin = static_cast<std::uint32_t>(magnitude(level, std::size_t{y} * w + x) * per_bin);
          ++scratch.histogram[bin < kBins ? bin : kBins - 1];
          ++n;
        }
      std::uint32_t sum = 0, median_bin = 0;
      for (; median_bin < kBins; ++median_bin) {
        sum += scratch.histogram[median_bin];
        if (2 * sum >= n) break;
      }
      scratch.block_threshold[std::size_t{by} * bw + bx] =
          (static_cast<float>(median_bin) + 0.5f) * bin_width + margin_counts;
    }

  // Grid cells sized for the wanted count; shrink the cell when too few points are found.
  std::size_t count = 0;
  float cell = std::sqrt(static_cast<float>(w) * static_cast<float>(h) / static_cast<float>(wanted ? wanted : 1));
  for (int attempt = 0; attempt < 3; ++attempt) {
    count = 0;
    const auto c = static_cast<std::uint32_t>(cell < 2 ? 2 : cell);
    for (std::uint32_t cy = margin; cy + margin < h; cy += c)
      for (std::uint32_t cx = margin; cx + margin < w; cx += c) {
        PixelPoint best;
        float best_score = 0;
        for (std::uint32_t y = cy; y < cy + c && y + margin < h; ++y)
          for (std::uint32_t x = cx; x < cx + c && x + margin < w; ++x) {
            const std::size_t i = std::size_t{y} * w + x;
            if (!occupied.empty() && occupied[i]) continue;
            const float g = magnitude(level, i);
            const float excess = g - scratch.block_threshold[std::size_t{y / kBlock} * bw + x / kBlock];
            if (excess > best_score) {
              best_score = excess;
              best = {static_cast<std::uint16_t>(x), static_cast<std::uint16_t>(y), g};
            }
          }
        if (best_score > 0 && count < out.size()) out[count++] = best;
      }
    if (count * 10 >= std::size_t{wanted} * 7 || cell <= 2) break;
    cell *= 0.7f;
  }
  return count;
}

}  // namespace bolo::vo
