#include "bolo/firmware/nuc_stage.hpp"

#include <algorithm>

#include "bolo/firmware/detail/kernels.hpp"
#include "multiversion.hpp"
#if BOLO_NEON_KERNELS
#include "neon_nuc.hpp"
#endif

namespace bolo::fw {
namespace {

// The definition.
BOLO_KERNEL_CLONES
void nuc_line_portable(const Pixel* __restrict in, const std::uint16_t* __restrict gain_q14,
                       const std::int16_t* __restrict offset, Pixel* __restrict out,
                       std::size_t width) {
  for (std::size_t x = 0; x < width; ++x) out[x] = nuc_pixel(in[x], gain_q14[x], offset[x]);
}

#if BOLO_NEON_KERNELS
// 8 pixels a step in 16-bit lanes (neon::nuc_narrow); a line with a pixel or gain outside that
// case's range is done again in 32-bit lanes. The last width % 8 pixels: the portable loop.
// noinline: one symbol per pass, so scripts/board-cost.sh finds each loop.
template <bool kNarrow>
__attribute__((noinline)) bool nuc_line_neon_pass(const Pixel* __restrict in,
                                                  const std::uint16_t* __restrict gain,
                                                  const std::int16_t* __restrict offset,
                                                  Pixel* __restrict out, std::size_t width) {
  uint16x8_t in_range = vdupq_n_u16(0);
  std::size_t x = 0;
  for (; x + 8 <= width; x += 8) {
    const uint16x8_t v = vld1q_u16(in + x);
    const uint16x8_t g = vld1q_u16(gain + x);
    const int16x8_t o = vld1q_s16(offset + x);
    vst1q_u16(out + x, kNarrow ? neon::nuc_narrow(v, g, o, in_range) : neon::nuc_wide(v, g, o));
  }
  if (kNarrow && neon::narrow_out_of_range(in_range)) return false;
  nuc_line_portable(in + x, gain + x, offset + x, out + x, width - x);
  return true;
}

void nuc_line_neon(const Pixel* __restrict in, const std::uint16_t* __restrict gain_q14,
                   const std::int16_t* __restrict offset, Pixel* __restrict out,
                   std::size_t width) {
  if (!nuc_line_neon_pass<true>(in, gain_q14, offset, out, width))
    nuc_line_neon_pass<false>(in, gain_q14, offset, out, width);
}
#endif

}  // namespace

void nuc_line(const Pixel* __restrict in, const std::uint16_t* __restrict gain_q14,
              const std::int16_t* __restrict offset, Pixel* __restrict out, std::size_t width) {
#if BOLO_NEON_KERNELS
  nuc_line_neon(in, gain_q14, offset, out, width);
#else
  nuc_line_portable(in, gain_q14, offset, out, width);
#endif
}

namespace detail {
NucLineFn nuc_line_kernel(KernelPath path) {
  switch (path) {
    case KernelPath::portable: return nuc_line_portable;
#if BOLO_NEON_KERNELS
    case KernelPath::neon: return nuc_line_neon;
#endif
    default: break;
  }
  return nullptr;
}
}  // namespace detail

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
