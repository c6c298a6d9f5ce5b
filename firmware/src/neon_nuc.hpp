#pragma once
// The NUC (nuc_pixel) on 8 pixels in NEON registers, shared by nuc_line and the bad-pixel intake.
// Only where BOLO_NEON_KERNELS is 1.
//
// Narrow: 16-bit lanes, valid when every pixel is below 2^14 and every gain below 2^15 (Q2.14
// gains under 2.0). With in2 = 2 in, both non-negative int16, vqrdmulh gives
// (2 in2 gain + 2^15) >> 16 = (in gain + 2^13) >> 14: nuc_pixel's `scaled`, at most 32767. The
// offset is then added with unsigned saturation (aarch64: usqadd; armv7: a signed saturating add
// on values biased by -32768), which is the clamp to [0, 65535] (the sum is at most 65534).
// in2 is a saturating add, so its bit 15 is set for every pixel at or above 2^14: bit 15 of
// in2 | gain, gathered over a line, says whether the line must be done again the wide way.
// Wide: every input; the u32 product, rounded shift, sign-extended offset in 32-bit lanes,
// saturating narrow to u16.

#include <arm_neon.h>

#include <cstdint>

#include "bolo/firmware/nuc_stage.hpp"

namespace bolo::fw::neon {

inline uint16x8_t nuc_wide(uint16x8_t in, uint16x8_t gain, int16x8_t offset) {
  static_assert(kNucGainFractionBits == 14);
  // (p + 2^13) >> 14 with p < 2^32: the rounding shift does not overflow.
  const int32x4_t lo = vreinterpretq_s32_u32(
      vrshrq_n_u32(vmull_u16(vget_low_u16(in), vget_low_u16(gain)), 14));
  const int32x4_t hi = vreinterpretq_s32_u32(
      vrshrq_n_u32(vmull_u16(vget_high_u16(in), vget_high_u16(gain)), 14));
  return vcombine_u16(vqmovun_s32(vaddw_s16(lo, vget_low_s16(offset))),
                      vqmovun_s32(vaddw_s16(hi, vget_high_s16(offset))));
}

// `range` is set to 2 in | gain, whose bit 15 marks a lane outside the narrow case (see above).
inline uint16x8_t nuc_narrow(uint16x8_t in, uint16x8_t gain, int16x8_t offset,
                             uint16x8_t& range) {
  const uint16x8_t in2 = vqaddq_u16(in, in);
  range = vorrq_u16(in2, gain);
  const int16x8_t scaled = vqrdmulhq_s16(vreinterpretq_s16_u16(in2), vreinterpretq_s16_u16(gain));
#if defined(__aarch64__)
  return vsqaddq_u16(vreinterpretq_u16_s16(scaled), offset);
#else
  const int16x8_t flip = vdupq_n_s16(INT16_MIN);
  return vreinterpretq_u16_s16(veorq_s16(vqaddq_s16(veorq_s16(scaled, flip), offset), flip));
#endif
}

// Whether some lane of nuc_narrow's range (OR-ed over a line) has bit 15 set.
inline bool narrow_out_of_range(uint16x8_t in_range) {
  const uint8x8_t high_bytes = vshrn_n_u16(in_range, 8);
  return (vget_lane_u64(vreinterpret_u64_u8(high_bytes), 0) & 0x8080808080808080u) != 0;
}

}  // namespace bolo::fw::neon
