#pragma once
// The NUC (nuc_pixel) on 32 pixels in AVX-512 registers, shared by the bad-pixel intake
// (bad_pixel_ingest.cpp) and the Pipeline's fused pass (correct_line.cpp). Include after
// <immintrin.h>, where BOLO_X86_KERNELS is 1.

#include "bolo/firmware/nuc_stage.hpp"

namespace bolo::fw::detail::nuc_simd {

#define BOLO_NUC_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,avx2")))

// The general case: mulhi/mullo give the u32 product in*gain as two halves; unpacklo/hi_epi16
// assemble it in 32-bit lanes (pixels 8j+0..3 and 8j+4..7 of each 128-bit lane), the offset is
// sign-extended the same way, and packus_epi32 (within 128-bit lanes again) restores pixel
// order while saturating the int32 sum to [0, 65535]: exactly nuc_pixel's clamp. in*gain + 2^13
// < 2^32, so the logical shift is exact. `half` is 2^13 in every 32-bit lane.
BOLO_NUC_AVX512 inline __attribute__((always_inline)) __m512i wide(__m512i v, __m512i g,
                                                                   __m512i o, __m512i half) {
  const __m512i hi = _mm512_mulhi_epu16(v, g);
  const __m512i lo = _mm512_mullo_epi16(v, g);
  const __m512i sign = _mm512_srai_epi16(o, 15);
  const __m512i v0 = _mm512_add_epi32(
      _mm512_srli_epi32(_mm512_add_epi32(_mm512_unpacklo_epi16(lo, hi), half),
                        kNucGainFractionBits),
      _mm512_unpacklo_epi16(o, sign));
  const __m512i v1 = _mm512_add_epi32(
      _mm512_srli_epi32(_mm512_add_epi32(_mm512_unpackhi_epi16(lo, hi), half),
                        kNucGainFractionBits),
      _mm512_unpackhi_epi16(o, sign));
  return _mm512_packus_epi32(v0, v1);
}

// The usual case in 16-bit lanes, valid when the pixel is below 2^14 and the gain below 2^15
// (Q2.14 gains under 2.0); `in2` is 2 in. Then 2 in and gain are non-negative int16 and mulhrs
// gives (2 in * gain + 2^14) >> 15 = (in * gain + 2^13) >> 14, exactly nuc_pixel's `scaled`, at
// most 32767. Biased by -32768 (bit 15 flipped; `flip` is 0x8000 in every 16-bit lane) it is in
// [-32768, -1]; a signed saturating add of the offset is then exactly the clamp to [0, 65535]
// once the bias is flipped back (the sum cannot exceed 32766, and everything at or below -32768
// is 0).
BOLO_NUC_AVX512 inline __attribute__((always_inline)) __m512i narrow(__m512i in2, __m512i g,
                                                                     __m512i o, __m512i flip) {
  const __m512i scaled = _mm512_mulhrs_epi16(in2, g);
  return _mm512_xor_si512(_mm512_adds_epi16(_mm512_xor_si512(scaled, flip), o), flip);
}

#undef BOLO_NUC_AVX512

}  // namespace bolo::fw::detail::nuc_simd
