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
// case's range is done again in 32-bit lanes. Four steps per iteration, loads first, so that an
// in-order core has independent work while each step's multiply completes. The last width % 32
// pixels: the portable loop.
// noinline: one symbol per pass, so scripts/board-cost.sh finds each loop.
template <bool kNarrow>
__attribute__((noinline)) bool nuc_line_neon_pass(const Pixel* __restrict in,
                                                  const std::uint16_t* __restrict gain,
                                                  const std::int16_t* __restrict offset,
                                                  Pixel* __restrict out, std::size_t width) {
  constexpr std::size_t kSteps = 4;
  uint16x8_t in_range = vdupq_n_u16(0);
  std::size_t x = 0;
  for (; x + 8 * kSteps <= width; x += 8 * kSteps) {
    uint16x8_t v[kSteps], g[kSteps], range[kSteps];
    int16x8_t o[kSteps];
    for (std::size_t s = 0; s < kSteps; ++s) {
      v[s] = vld1q_u16(in + x + 8 * s);
      g[s] = vld1q_u16(gain + x + 8 * s);
      o[s] = vld1q_s16(offset + x + 8 * s);
    }
    for (std::size_t s = 0; s < kSteps; ++s)
      vst1q_u16(out + x + 8 * s, kNarrow ? neon::nuc_narrow(v[s], g[s], o[s], range[s])
                                         : neon::nuc_wide(v[s], g[s], o[s]));
    if constexpr (kNarrow)
      in_range = vorrq_u16(in_range, vorrq_u16(vorrq_u16(range[0], range[1]),
                                               vorrq_u16(range[2], range[3])));
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
