#include "bolo/core/frame_collector.hpp"

#include <algorithm>

namespace bolo::fw {

FrameCollector::FrameCollector(std::uint32_t width, std::uint32_t height, std::span<Pixel> storage)
    : width_(width),
      height_(height),
      storage_(storage.first(std::min(storage.size(), storage_pixels(width, height)))) {}

void FrameCollector::begin_frame(const FrameHeader& header) {
  header_ = header;
  lines_ = 0;
  intact_ = header.width == width_ && header.height == height_;
}

void FrameCollector::push_line(std::uint32_t row, LineView line) {
  if (row != lines_ || row >= height_ || line.size() != width_) intact_ = false;
  const std::size_t at = std::size_t{row} * width_;
  if (row < height_ && at < storage_.size()) {
    const std::size_t n = std::min({line.size(), std::size_t{width_}, storage_.size() - at});
    std::copy_n(line.begin(), n, storage_.begin() + static_cast<std::ptrdiff_t>(at));
  }
  ++lines_;
  last_row_ = row;
}

}  // namespace bolo::fw
