#include "bolo/firmware/bad_pixel_stage.hpp"

#include <algorithm>

namespace bolo::fw {

BadPixelStage::BadPixelStage(const BadPixelConfig& config, std::span<Pixel> storage,
                             LineSink& next)
    : Stage(next), config_(config), width_(config.width), height_(config.height) {
  const std::size_t frame = std::size_t{width_} * height_;
  if (storage.size() < storage_pixels(width_) || (!config.mask.empty() && config.mask.size() < frame)) {
    width_ = 0;  // misconfigured: every frame passes through untouched
    height_ = 0;
    return;
  }
  ring_ = storage.subspan(0, std::size_t{width_} * 3);
  flags_ = storage.subspan(std::size_t{width_} * 3, std::size_t{width_} * 3);
  out_line_ = storage.subspan(std::size_t{width_} * 6, width_);
}

void BadPixelStage::begin_frame(const FrameHeader& header) {
  active_ = width_ != 0 && header.width == width_ && header.height == height_;
  rows_in_ = 0;
  stats_ = BadPixelFrameStats{};
  next().begin_frame(header);
}

void BadPixelStage::push_line(std::uint32_t row, LineView line) {
  if (!active_ || row != rows_in_ || line.size() != width_) {
    // Out of order or mis-sized: the neighbourhood is meaningless, so stop repairing this frame
    // but still deliver what is buffered in order.
    if (active_ && rows_in_ > 0) emit(rows_in_ - 1);
    active_ = false;
    next().push_line(row, line);
    return;
  }
  std::copy(line.begin(), line.end(), ring_line(row));
  Pixel* flags = ring_flags(row);
  const std::uint8_t* mask =
      config_.mask.empty() ? nullptr : config_.mask.data() + std::size_t{row} * width_;
  for (std::uint32_t x = 0; x < width_; ++x) {
    const Pixel v = line[x];
    const bool stuck = config_.detect_stuck && (v == config_.stuck_low || v == config_.stuck_high);
    flags[x] = (stuck || (mask != nullptr && mask[x] != 0)) ? 1 : 0;
  }
  rows_in_ = row + 1;
  if (row >= kRadius) emit(row - kRadius);
}

void BadPixelStage::emit(std::uint32_t row) {
  const std::uint32_t first = row == 0 ? 0 : row - 1;
  const std::uint32_t last = std::min(row + 1, rows_in_ - 1);
  const Pixel* centre = ring_line(row);
  const Pixel* centre_flags = ring_flags(row);
  for (std::uint32_t x = 0; x < width_; ++x) {
    if (centre_flags[x] == 0) {
      out_line_[x] = centre[x];
      continue;
    }
    const std::uint32_t x0 = x == 0 ? 0 : x - 1;
    const std::uint32_t x1 = std::min(x + 1, width_ - 1);
    std::uint32_t sum = 0;
    std::uint32_t count = 0;
    for (std::uint32_t r = first; r <= last; ++r) {
      const Pixel* values = ring_line(r);
      const Pixel* flags = ring_flags(r);
      for (std::uint32_t c = x0; c <= x1; ++c) {
        if (flags[c] == 0) {
          sum += values[c];
          ++count;
        }
      }
    }
    if (count == 0) {
      out_line_[x] = centre[x];
      ++stats_.unrepairable;
    } else {
      out_line_[x] = static_cast<Pixel>((sum + count / 2) / count);  // nearest, ties up
      ++stats_.replaced;
    }
  }
  next().push_line(row, LineView(out_line_.data(), width_));
}

void BadPixelStage::end_frame() {
  if (active_ && rows_in_ > 0) emit(rows_in_ - 1);
  active_ = false;
  next().end_frame();
}

}  // namespace bolo::fw
