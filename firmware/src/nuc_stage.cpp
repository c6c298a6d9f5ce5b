#include "bolo/firmware/nuc_stage.hpp"

#include <algorithm>

#include "multiversion.hpp"

namespace bolo::fw {

BOLO_KERNEL_CLONES
void nuc_line(const Pixel* __restrict in, const std::uint16_t* __restrict gain_q14,
              const std::int16_t* __restrict offset, Pixel* __restrict out, std::size_t width) {
  for (std::size_t x = 0; x < width; ++x) out[x] = nuc_pixel(in[x], gain_q14[x], offset[x]);
}

NucStage::NucStage(std::uint32_t width, std::uint32_t height, NucTables tables,
                   std::span<Pixel> storage, LineSink& next)
    : Stage(next), width_(width), height_(height), tables_(tables) {
  const std::size_t frame = std::size_t{width} * height;
  if (storage.size() < storage_pixels(width) || tables.gain_q14.size() < frame ||
      tables.offset.size() < frame) {
    width_ = 0;  // misconfigured: every frame passes through untouched
    height_ = 0;
    return;
  }
  out_line_ = storage.subspan(0, width);
}

void NucStage::begin_frame(const FrameHeader& header) {
  active_ = width_ != 0 && header.width == width_ && header.height == height_;
  next().begin_frame(header);
}

void NucStage::push_line(std::uint32_t row, LineView line) {
  if (!active_ || row >= height_ || line.size() != width_) {
    next().push_line(row, line);
    return;
  }
  const std::size_t at = std::size_t{row} * width_;
  nuc_line(line.data(), tables_.gain_q14.data() + at, tables_.offset.data() + at,
           out_line_.data(), width_);
  next().push_line(row, LineView(out_line_.data(), width_));
}

void NucStage::end_frame() { next().end_frame(); }

}  // namespace bolo::fw
