#include "bolo/firmware/bad_pixel_stage.hpp"

#include <algorithm>
#include <cstring>

#include "multiversion.hpp"

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

namespace {

// Copies a raw line into the ring and flags its bad pixels (1 = bad, 0 = good); returns how many
// it flagged. One loop per configuration so each one vectorises (no per-pixel tests of the
// configuration, and no reloads of it through the aliasing `Pixel*` stores).
BOLO_KERNEL_CLONES
std::uint32_t copy_and_flag(const Pixel* __restrict in, const std::uint8_t* __restrict mask,
                            bool detect_stuck, Pixel stuck_low, Pixel stuck_high,
                            Pixel* __restrict ring, Pixel* __restrict flags, std::size_t width) {
  std::uint32_t count = 0;
  if (detect_stuck && mask != nullptr) {
    for (std::size_t x = 0; x < width; ++x) {
      const Pixel v = in[x];
      ring[x] = v;
      const Pixel f = static_cast<Pixel>((v == stuck_low) | (v == stuck_high) | (mask[x] != 0));
      flags[x] = f;
      count += f;
    }
  } else if (detect_stuck) {
    for (std::size_t x = 0; x < width; ++x) {
      const Pixel v = in[x];
      ring[x] = v;
      const Pixel f = static_cast<Pixel>((v == stuck_low) | (v == stuck_high));
      flags[x] = f;
      count += f;
    }
  } else if (mask != nullptr) {
    for (std::size_t x = 0; x < width; ++x) {
      ring[x] = in[x];
      const Pixel f = static_cast<Pixel>(mask[x] != 0);
      flags[x] = f;
      count += f;
    }
  } else {
    for (std::size_t x = 0; x < width; ++x) {
      ring[x] = in[x];
      flags[x] = 0;
    }
  }
  return count;
}

constexpr std::uint32_t kBlock = 32;  // flag scan: pixels tested together in emit()

// Whether any of `n` flags is set; a whole block is read as 64-bit words (flags are 0 or 1).
inline bool block_has_flag(const Pixel* flags, std::uint32_t n) {
  if (n == kBlock) {
    std::uint64_t words[kBlock * sizeof(Pixel) / sizeof(std::uint64_t)];
    std::memcpy(words, flags, sizeof words);
    std::uint64_t any = 0;
    for (std::uint64_t w : words) any |= w;
    return any != 0;
  }
  Pixel any = 0;
  for (std::uint32_t x = 0; x < n; ++x) any = static_cast<Pixel>(any | flags[x]);
  return any != 0;
}

}  // namespace

void BadPixelStage::push_line(std::uint32_t row, LineView line) {
  if (!active_ || row != rows_in_ || row >= height_ || line.size() != width_) {
    // Out of order or mis-sized: the neighbourhood is meaningless, so stop repairing this frame
    // but still deliver what is buffered in order.
    if (active_ && rows_in_ > 0) emit(rows_in_ - 1);
    active_ = false;
    next().push_line(row, line);
    return;
  }
  const std::uint8_t* mask =
      config_.mask.empty() ? nullptr : config_.mask.data() + std::size_t{row} * width_;
  flag_count_[row % 3] = copy_and_flag(line.data(), mask, config_.detect_stuck, config_.stuck_low,
                                       config_.stuck_high, ring_line(row), ring_flags(row), width_);
  rows_in_ = row + 1;
  if (row >= kRadius) emit(row - kRadius);
}

void BadPixelStage::emit(std::uint32_t row) {
  const Pixel* centre = ring_line(row);
  std::uint32_t remaining = flag_count_[row % 3];
  if (remaining == 0) {
    // Nothing to repair: the ring line itself goes on (it is not touched before the next push).
    next().push_line(row, LineView(centre, width_));
    return;
  }
  const std::uint32_t first = row == 0 ? 0 : row - 1;
  const std::uint32_t last = std::min(row + 1, rows_in_ - 1);
  const Pixel* centre_flags = ring_flags(row);
  std::copy(centre, centre + width_, out_line_.data());
  // Only flagged pixels change; whole blocks without a flag are skipped.
  for (std::uint32_t block = 0; block < width_ && remaining != 0; block += kBlock) {
    const std::uint32_t end = std::min(block + kBlock, width_);
    if (!block_has_flag(centre_flags + block, end - block)) continue;
    for (std::uint32_t x = block; x < end; ++x) {
      if (centre_flags[x] == 0) continue;
      --remaining;
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
        ++stats_.unrepairable;  // passed through: out_line_ already holds the centre value
      } else {
        out_line_[x] = static_cast<Pixel>((sum + count / 2) / count);  // nearest, ties up
        ++stats_.replaced;
      }
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
