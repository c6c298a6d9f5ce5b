// The per-pixel kernels of the two-frame corrector.
//
// The portable loop is the definition: unsigned 64-bit products of u16 x u32, a bias that keeps
// the difference non-negative so a logical shift does the rounding division, then 32-bit
// clamping. On x86-64 (GCC) hand-written AVX2 and AVX-512 versions are picked at run time; they
// compute the same integers with 16-bit multiply-adds (see "16-bit multiply-adds" below) and
// tests/firmware/test_kernels.cpp checks every one against the portable loop, output and counts.
// On ARM with NEON a NEON version is chosen at build time (see "NEON" below), tested the same way.

#include <cstddef>
#include <cstdint>

#include "bolo/firmware/detail/kernels.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "simd_intrinsics.hpp"

namespace bolo::fw {
namespace {

constexpr unsigned kShift = kCoefficientFractionBits;
constexpr std::uint64_t kHalf = std::uint64_t{1} << (kShift - 1);
// G * cur < 2^48 and A * prev < 2^48: adding 2^48 makes G*cur - A*prev + half non-negative.
constexpr std::uint64_t kBias = std::uint64_t{1} << 48;
constexpr std::int32_t kBiasShifted = std::int32_t{1} << (48 - kShift);
constexpr std::int32_t kMaxOut = 0xFFFF;

// The definition. `kStore`: previous[x] = current[x] after use (the frame-store update).
template <bool kStore>
inline void correct_portable(const Pixel* __restrict current, Pixel* __restrict previous,
                             CorrectorCoefficients c, Pixel* __restrict out, std::size_t width,
                             std::uint32_t& low, std::uint32_t& high) {
  const std::uint64_t gain = c.gain_q24;
  const std::uint64_t carry = c.carry_q24;
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  for (std::size_t x = 0; x < width; ++x) {
    const Pixel cur = current[x];
    const std::uint64_t biased = cur * gain + (kBias + kHalf) - previous[x] * carry;
    if constexpr (kStore) previous[x] = cur;
    // floor((d + half) / 2^24): round to nearest, ties away from zero for d >= 0; every d < 0
    // clamps to 0 whichever way it rounds.
    const std::int32_t value = static_cast<std::int32_t>(biased >> kShift) - kBiasShifted;
    n_low += value < 0 ? 1u : 0u;
    n_high += value > kMaxOut ? 1u : 0u;
    const std::int32_t clamped = value < 0 ? 0 : (value > kMaxOut ? kMaxOut : value);
    out[x] = static_cast<Pixel>(clamped);
  }
  low += n_low;
  high += n_high;
}

void correct_line_portable(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                           Pixel* out, std::size_t width, std::uint32_t& low,
                           std::uint32_t& high) {
  // kStore = false never writes through the pointer.
  correct_portable<false>(current, const_cast<Pixel*>(previous), c, out, width, low, high);
}

void correct_update_portable(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                             Pixel* out, std::size_t width, std::uint32_t& low,
                             std::uint32_t& high) {
  correct_portable<true>(current, previous, c, out, width, low, high);
}

#if BOLO_X86_KERNELS
// ---- SIMD kernels (AVX2 and AVX-512 alike): see "16-bit multiply-adds" below ----
// Counts: value < 0 and value > 65535 on the int32 lanes, as in the portable loop; computed only
// for the steps where some lane has a bit set above bit 15 (a value outside [0, 65535]).

#define BOLO_AVX2 __attribute__((target("avx2")))

inline std::uint32_t popcount8(int bits) {
  return static_cast<std::uint32_t>(__builtin_popcount(static_cast<unsigned>(bits) & 0xFFu));
}
inline std::uint32_t popcount16(__mmask16 bits) {
  return static_cast<std::uint32_t>(__builtin_popcount(bits));
}
#define BOLO_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,avx2")))
// The same with AVX512-VNNI (vpdpwssd: the multiply-add and the following 32-bit add in one
// instruction; wrapping, like vpmaddwd + vpaddd, so the integers are the same).
#define BOLO_AVX512_VNNI \
  __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,avx512vnni,avx2")))

// ---- 16-bit multiply-adds on the natural pixel layout (AVX-512 and AVX2) ----
// (v)pmaddwd multiplies signed 16-bit pairs and adds each pair into a 32-bit lane, 32 products
// per instruction without splitting pixels into wider lanes. The pixels are made signed by
// flipping bit 15 (p' = p - 32768) and interleaved as (cur', prev') pairs; G and A are cut into
// digits G = g2*2^28 + g1*2^14 + g0 (g0, g1 < 2^14, g2 < 16), so each pair sum
//   P_k = g_k*cur' - a_k*prev'   has |P_k| < 2^30: no overflow.
// With K = 32768*(G - A) + 2^23 = Kh*2^24 + Kl (0 <= Kl < 2^24):
//   G*cur - A*prev + 2^23 = 2^28 P2 + 2^14 P1 + P0 + K, and for integers
//   floor((2^28 P2 + 2^14 P1 + P0 + K) / 2^24) = Kh + 16 P2 + ((P1 + ((P0 + Kl) >> 14)) >> 10)
// with arithmetic shifts (nested floor divisions), every term inside int32. That is exactly the
// portable loop's `value`. When G and A are below 2^28 (g < 16, every realistic exposure) g2 and
// a2 are 0 and the P2 term is left out: two multiply-adds per pair instead of three.
// unpacklo/hi_epi16 and packus_epi32 both work within 128-bit lanes and
// undo each other's order, so the packed result is in pixel order; packus is the clamp.
struct MaddCoefficients {
  std::uint32_t digit0, digit1, digit2x16;  // lanes: low 16 bits g_k, high 16 bits -a_k
  std::int32_t k_high, k_low;
};

inline std::uint32_t digit_pair(std::uint32_t g, std::uint32_t a) {
  const auto minus_a = static_cast<std::uint16_t>(0u - a);  // -a as int16 bits, a < 2^14 * 16
  return g | (std::uint32_t{minus_a} << 16);
}

inline MaddCoefficients madd_coefficients(CorrectorCoefficients c) {
  constexpr std::uint32_t kDigit = (1u << 14) - 1;
  const std::uint32_t g = c.gain_q24, a = c.carry_q24;
  const std::int64_t k = std::int64_t{32768} * (std::int64_t{g} - std::int64_t{a}) +
                         static_cast<std::int64_t>(kHalf);
  return {digit_pair(g & kDigit, a & kDigit), digit_pair((g >> 14) & kDigit, (a >> 14) & kDigit),
          digit_pair((g >> 28) << 4, (a >> 28) << 4), static_cast<std::int32_t>(k >> kShift),
          static_cast<std::int32_t>(k & ((std::int64_t{1} << kShift) - 1))};
}

struct Avx512Constants {
  __m512i flip, d0, d1, d2, k_high, k_low, above16, max_out;
  __m512i half, input_above15;  // for blocks of inputs below 2^15 (see avx512_vnni_block)
};

// The value (as the portable loop's) of the pixels interleaved in `pairs`. `kWide`: G or A is
// 2^28 or more, so the third digit counts.
template <bool kWide>
BOLO_AVX512 inline __attribute__((always_inline)) __m512i avx512_values(__m512i pairs,
                                                                        const Avx512Constants& k) {
  const __m512i t0 = _mm512_srai_epi32(_mm512_add_epi32(_mm512_madd_epi16(pairs, k.d0), k.k_low), 14);
  const __m512i t1 = _mm512_srai_epi32(_mm512_add_epi32(_mm512_madd_epi16(pairs, k.d1), t0), 10);
  if constexpr (kWide) return _mm512_add_epi32(_mm512_add_epi32(_mm512_madd_epi16(pairs, k.d2), k.k_high), t1);
  return _mm512_add_epi32(t1, k.k_high);
}

// The same sums with vpdpwssd (accumulator + the pair's two products): 5 instructions per
// vector in the usual case instead of 7.
template <bool kWide>
BOLO_AVX512_VNNI inline __attribute__((always_inline)) __m512i avx512_vnni_values(
    __m512i pairs, const Avx512Constants& k) {
  const __m512i t0 = _mm512_srai_epi32(_mm512_dpwssd_epi32(k.k_low, pairs, k.d0), 14);
  const __m512i t1 = _mm512_srai_epi32(_mm512_dpwssd_epi32(t0, pairs, k.d1), 10);
  if constexpr (kWide) return _mm512_dpwssd_epi32(_mm512_add_epi32(t1, k.k_high), pairs, k.d2);
  return _mm512_add_epi32(t1, k.k_high);
}

// One step of 32 pixels; `m` selects the pixels that exist (all but in the last step).
// Missing pixels load as 0 for both frames and give value floor(2^23 / 2^24) = 0: they count
// nowhere and are never stored. A step is the loads, the frame-store update and the pairs
// (avx512_pairs), the values of both pair vectors, and the counts and the store (avx512_finish).
struct Avx512Pairs {
  __m512i lo, hi;  // pixels 8j + 0..3 and 8j + 4..7 of each 128-bit lane
};

template <bool kStore>
BOLO_AVX512 inline __attribute__((always_inline)) Avx512Pairs avx512_pairs(
    const Pixel* __restrict current, Pixel* __restrict previous, std::size_t x, __mmask32 m,
    const Avx512Constants& k) {
  const __m512i cur = _mm512_maskz_loadu_epi16(m, current + x);
  const __m512i prev = _mm512_maskz_loadu_epi16(m, previous + x);
  if constexpr (kStore) _mm512_mask_storeu_epi16(previous + x, m, cur);
  const __m512i cs = _mm512_xor_si512(cur, k.flip);
  const __m512i ps = _mm512_xor_si512(prev, k.flip);
  return {_mm512_unpacklo_epi16(cs, ps), _mm512_unpackhi_epi16(cs, ps)};
}

BOLO_AVX512 inline __attribute__((always_inline)) void avx512_finish(
    __m512i vlo, __m512i vhi, Pixel* __restrict out, std::size_t x, __mmask32 m,
    const Avx512Constants& k, std::uint32_t& n_low, std::uint32_t& n_high) {
  // A value outside [0, 65535] has a bit set above bit 15 (negative ones: the sign). Rare, so one
  // test per step, and the exact counts only where it fires.
  if (_mm512_test_epi32_mask(_mm512_or_si512(vlo, vhi), k.above16) != 0) [[unlikely]] {
    const __m512i zero = _mm512_setzero_si512();
    n_low += popcount16(_mm512_cmplt_epi32_mask(vlo, zero)) +
             popcount16(_mm512_cmplt_epi32_mask(vhi, zero));
    n_high += popcount16(_mm512_cmpgt_epi32_mask(vlo, k.max_out)) +
              popcount16(_mm512_cmpgt_epi32_mask(vhi, k.max_out));
  }
  _mm512_mask_storeu_epi16(out + x, m, _mm512_packus_epi32(vlo, vhi));
}

template <bool kStore, bool kWide>
BOLO_AVX512 inline __attribute__((always_inline)) void avx512_step(
    const Pixel* __restrict current, Pixel* __restrict previous, Pixel* __restrict out,
    std::size_t x, __mmask32 m, const Avx512Constants& k, std::uint32_t& n_low,
    std::uint32_t& n_high) {
  const Avx512Pairs p = avx512_pairs<kStore>(current, previous, x, m, k);
  avx512_finish(avx512_values<kWide>(p.lo, k), avx512_values<kWide>(p.hi, k), out, x, m, k,
                n_low, n_high);
}

// The same step with vpdpwssd. A separate function, not a template flag: its target attribute
// allows VNNI instructions, which the plain kernel must never contain.
template <bool kStore, bool kWide>
BOLO_AVX512_VNNI inline __attribute__((always_inline)) void avx512_vnni_step(
    const Pixel* __restrict current, Pixel* __restrict previous, Pixel* __restrict out,
    std::size_t x, __mmask32 m, const Avx512Constants& k, std::uint32_t& n_low,
    std::uint32_t& n_high) {
  const Avx512Pairs p = avx512_pairs<kStore>(current, previous, x, m, k);
  avx512_finish(avx512_vnni_values<kWide>(p.lo, k), avx512_vnni_values<kWide>(p.hi, k), out, x,
                m, k, n_low, n_high);
}

// ---- Blocks of 128 pixels below 2^15 (the usual case: 14-bit data) ----
// A pixel below 2^15 is already a non-negative int16, so its pairs need no bit flip and K is
// 2^23 alone (Kh = 0, Kl = 2^23): per pair vector only the multiply-adds and shifts remain,
// value = 16 P2 + ((P1 + ((P0 + 2^23) >> 14)) >> 10). The per-step test for values outside
// [0, 65535] becomes one three-way OR per step: the inputs (bit 15) and the values (bits 16..31)
// are gathered over the block and tested once at its end. A block with an input at or above 2^15
// or a value out of range is done again the general way (flip, exact counts) from the inputs
// still in registers: the frame store is updated as each step loads it (deferring those stores
// until after the test would cost throughput from DRAM). Outputs of a block that passes are the
// general way's (same integers), counts 0.
constexpr std::size_t kBlockSteps = 4;

template <bool kWide>
BOLO_AVX512_VNNI inline __attribute__((always_inline)) __m512i avx512_vnni_unflipped_values(
    __m512i pairs, const Avx512Constants& k) {
  const __m512i t0 = _mm512_srai_epi32(_mm512_dpwssd_epi32(k.half, pairs, k.d0), 14);
  const __m512i t1 = _mm512_srai_epi32(_mm512_dpwssd_epi32(t0, pairs, k.d1), 10);
  if constexpr (kWide) return _mm512_dpwssd_epi32(t1, pairs, k.d2);
  return t1;
}

template <bool kStore, bool kWide>
BOLO_AVX512_VNNI inline __attribute__((always_inline)) void avx512_vnni_block(
    const Pixel* __restrict current, Pixel* __restrict previous, Pixel* __restrict out,
    std::size_t x, const Avx512Constants& k, std::uint32_t& n_low, std::uint32_t& n_high) {
  __m512i cur[kBlockSteps], prev[kBlockSteps];
  __m512i inputs = _mm512_setzero_si512();
  __m512i values = _mm512_setzero_si512();
  for (std::size_t s = 0; s < kBlockSteps; ++s) {
    const std::size_t at = x + 32 * s;
    cur[s] = _mm512_loadu_si512(current + at);
    prev[s] = _mm512_loadu_si512(previous + at);
    if constexpr (kStore) _mm512_storeu_si512(previous + at, cur[s]);
    inputs = _mm512_ternarylogic_epi32(inputs, cur[s], prev[s], 0xFE);  // a | b | c
    const __m512i vlo =
        avx512_vnni_unflipped_values<kWide>(_mm512_unpacklo_epi16(cur[s], prev[s]), k);
    const __m512i vhi =
        avx512_vnni_unflipped_values<kWide>(_mm512_unpackhi_epi16(cur[s], prev[s]), k);
    values = _mm512_ternarylogic_epi32(values, vlo, vhi, 0xFE);
    _mm512_storeu_si512(out + at, _mm512_packus_epi32(vlo, vhi));
  }
  if (_kortestz_mask16_u8(_mm512_test_epi32_mask(inputs, k.input_above15),
                          _mm512_test_epi32_mask(values, k.above16)) == 0) [[unlikely]] {
    for (std::size_t s = 0; s < kBlockSteps; ++s) {  // the general way, as avx512_vnni_step
      const __m512i cs = _mm512_xor_si512(cur[s], k.flip);
      const __m512i ps = _mm512_xor_si512(prev[s], k.flip);
      avx512_finish(avx512_vnni_values<kWide>(_mm512_unpacklo_epi16(cs, ps), k),
                    avx512_vnni_values<kWide>(_mm512_unpackhi_epi16(cs, ps), k), out,
                    x + 32 * s, ~__mmask32{0}, k, n_low, n_high);
    }
  }
}

inline __mmask32 tail_mask(std::size_t n) {
  return static_cast<__mmask32>((std::uint32_t{1} << n) - 1u);
}

template <bool kStore, bool kWide>
BOLO_AVX512 void correct_avx512_loop(const Pixel* __restrict current, Pixel* __restrict previous,
                                     const Avx512Constants& k, Pixel* __restrict out,
                                     std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  std::size_t x = 0;
  for (; x + 32 <= width; x += 32)
    avx512_step<kStore, kWide>(current, previous, out, x, ~__mmask32{0}, k, n_low, n_high);
  if (x < width)
    avx512_step<kStore, kWide>(current, previous, out, x, tail_mask(width - x), k, n_low, n_high);
  low += n_low;
  high += n_high;
}

template <bool kStore, bool kWide>
BOLO_AVX512_VNNI void correct_avx512_vnni_loop(const Pixel* __restrict current,
                                               Pixel* __restrict previous,
                                               const Avx512Constants& k, Pixel* __restrict out,
                                               std::size_t width, std::uint32_t& low,
                                               std::uint32_t& high) {
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  std::size_t x = 0;
  for (; x + 32 * kBlockSteps <= width; x += 32 * kBlockSteps)
    avx512_vnni_block<kStore, kWide>(current, previous, out, x, k, n_low, n_high);
  for (; x + 32 <= width; x += 32)
    avx512_vnni_step<kStore, kWide>(current, previous, out, x, ~__mmask32{0}, k, n_low, n_high);
  if (x < width)
    avx512_vnni_step<kStore, kWide>(current, previous, out, x, tail_mask(width - x), k, n_low,
                                    n_high);
  low += n_low;
  high += n_high;
}

BOLO_AVX512 inline Avx512Constants avx512_constants(const MaddCoefficients& mc) {
  return {_mm512_set1_epi16(static_cast<short>(0x8000)),
          _mm512_set1_epi32(static_cast<int>(mc.digit0)),
          _mm512_set1_epi32(static_cast<int>(mc.digit1)),
          _mm512_set1_epi32(static_cast<int>(mc.digit2x16)),
          _mm512_set1_epi32(mc.k_high),
          _mm512_set1_epi32(mc.k_low),
          _mm512_set1_epi32(static_cast<int>(0xFFFF0000u)),
          _mm512_set1_epi32(kMaxOut),
          _mm512_set1_epi32(static_cast<int>(kHalf)),
          _mm512_set1_epi16(static_cast<short>(0x8000))};
}

template <bool kStore>
BOLO_AVX512 void correct_avx512(const Pixel* __restrict current, Pixel* __restrict previous,
                                CorrectorCoefficients c, Pixel* __restrict out, std::size_t width,
                                std::uint32_t& low, std::uint32_t& high) {
  const MaddCoefficients mc = madd_coefficients(c);
  const Avx512Constants k = avx512_constants(mc);
  if (mc.digit2x16 != 0)
    correct_avx512_loop<kStore, true>(current, previous, k, out, width, low, high);
  else
    correct_avx512_loop<kStore, false>(current, previous, k, out, width, low, high);
}

template <bool kStore>
BOLO_AVX512_VNNI void correct_avx512_vnni(const Pixel* __restrict current,
                                          Pixel* __restrict previous, CorrectorCoefficients c,
                                          Pixel* __restrict out, std::size_t width,
                                          std::uint32_t& low, std::uint32_t& high) {
  const MaddCoefficients mc = madd_coefficients(c);
  const Avx512Constants k = avx512_constants(mc);
  if (mc.digit2x16 != 0)
    correct_avx512_vnni_loop<kStore, true>(current, previous, k, out, width, low, high);
  else
    correct_avx512_vnni_loop<kStore, false>(current, previous, k, out, width, low, high);
}

// ---- AVX2: the same multiply-add scheme on 256-bit vectors, 16 pixels per step ----
struct Avx2Constants {
  __m256i flip, d0, d1, d2, k_high, k_low, above16, max_out;
};

template <bool kWide>
BOLO_AVX2 inline __attribute__((always_inline)) __m256i avx2_values(__m256i pairs,
                                                                   const Avx2Constants& k) {
  const __m256i t0 = _mm256_srai_epi32(_mm256_add_epi32(_mm256_madd_epi16(pairs, k.d0), k.k_low), 14);
  const __m256i t1 = _mm256_srai_epi32(_mm256_add_epi32(_mm256_madd_epi16(pairs, k.d1), t0), 10);
  if constexpr (kWide) return _mm256_add_epi32(_mm256_add_epi32(_mm256_madd_epi16(pairs, k.d2), k.k_high), t1);
  return _mm256_add_epi32(t1, k.k_high);
}

template <bool kStore, bool kWide>
BOLO_AVX2 void correct_avx2_loop(const Pixel* __restrict current, Pixel* __restrict previous,
                                 const Avx2Constants& k, CorrectorCoefficients c,
                                 Pixel* __restrict out, std::size_t width, std::uint32_t& low,
                                 std::uint32_t& high) {
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  std::size_t x = 0;
  for (; x + 16 <= width; x += 16) {
    const __m256i cur = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(current + x));
    const __m256i prev = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(previous + x));
    if constexpr (kStore) _mm256_storeu_si256(reinterpret_cast<__m256i*>(previous + x), cur);
    const __m256i cs = _mm256_xor_si256(cur, k.flip);
    const __m256i ps = _mm256_xor_si256(prev, k.flip);
    const __m256i vlo = avx2_values<kWide>(_mm256_unpacklo_epi16(cs, ps), k);  // pixels 8j + 0..3
    const __m256i vhi = avx2_values<kWide>(_mm256_unpackhi_epi16(cs, ps), k);  // pixels 8j + 4..7
    // As in the AVX-512 kernel: one test per step, exact counts only where a value is out of range.
    if (!_mm256_testz_si256(_mm256_or_si256(vlo, vhi), k.above16)) [[unlikely]] {
      n_low += popcount8(_mm256_movemask_ps(_mm256_castsi256_ps(vlo))) +
               popcount8(_mm256_movemask_ps(_mm256_castsi256_ps(vhi)));
      n_high += popcount8(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(vlo, k.max_out)))) +
                popcount8(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(vhi, k.max_out))));
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + x), _mm256_packus_epi32(vlo, vhi));
  }
  low += n_low;
  high += n_high;
  correct_portable<kStore>(current + x, previous + x, c, out + x, width - x, low, high);
}

template <bool kStore>
BOLO_AVX2 void correct_avx2(const Pixel* __restrict current, Pixel* __restrict previous,
                            CorrectorCoefficients c, Pixel* __restrict out, std::size_t width,
                            std::uint32_t& low, std::uint32_t& high) {
  const MaddCoefficients mc = madd_coefficients(c);
  const Avx2Constants k{_mm256_set1_epi16(static_cast<short>(0x8000)),
                        _mm256_set1_epi32(static_cast<int>(mc.digit0)),
                        _mm256_set1_epi32(static_cast<int>(mc.digit1)),
                        _mm256_set1_epi32(static_cast<int>(mc.digit2x16)),
                        _mm256_set1_epi32(mc.k_high),
                        _mm256_set1_epi32(mc.k_low),
                        _mm256_set1_epi32(static_cast<int>(0xFFFF0000u)),
                        _mm256_set1_epi32(kMaxOut)};
  if (mc.digit2x16 != 0)
    correct_avx2_loop<kStore, true>(current, previous, k, c, out, width, low, high);
  else
    correct_avx2_loop<kStore, false>(current, previous, k, c, out, width, low, high);
}

void correct_line_avx2(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                       Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  correct_avx2<false>(current, const_cast<Pixel*>(previous), c, out, width, low, high);
}
void correct_update_avx2(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                         Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  correct_avx2<true>(current, previous, c, out, width, low, high);
}
void correct_line_avx512(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                         Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  correct_avx512<false>(current, const_cast<Pixel*>(previous), c, out, width, low, high);
}
void correct_update_avx512(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                           Pixel* out, std::size_t width, std::uint32_t& low,
                           std::uint32_t& high) {
  correct_avx512<true>(current, previous, c, out, width, low, high);
}
void correct_line_avx512_vnni(const Pixel* current, const Pixel* previous,
                              CorrectorCoefficients c, Pixel* out, std::size_t width,
                              std::uint32_t& low, std::uint32_t& high) {
  correct_avx512_vnni<false>(current, const_cast<Pixel*>(previous), c, out, width, low, high);
}
void correct_update_avx512_vnni(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                                Pixel* out, std::size_t width, std::uint32_t& low,
                                std::uint32_t& high) {
  correct_avx512_vnni<true>(current, previous, c, out, width, low, high);
}

bool cpu_has(detail::KernelPath path) {
  __builtin_cpu_init();
  switch (path) {
    case detail::KernelPath::portable: return true;
    case detail::KernelPath::avx2: return __builtin_cpu_supports("avx2");
    case detail::KernelPath::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx2");
    case detail::KernelPath::avx512_vnni:
      return cpu_has(detail::KernelPath::avx512) && __builtin_cpu_supports("avx512vnni");
    case detail::KernelPath::neon: return false;
  }
  return false;
}
#endif  // BOLO_X86_KERNELS

#if BOLO_NEON_KERNELS
// ---- NEON: widening 16-bit multiply-accumulates in 32-bit lanes, 8 pixels per step ----
// G and A are cut into 15-bit digits, G = g2*2^30 + g1*2^15 + g0 (g2 < 4), and likewise A.
// Each P_k = g_k*cur - a_k*prev is accumulated by vmull/vmlsl_u16 modulo 2^32; its true value
// lies in (-2^31, 2^31), so the lanes read as int32 hold it exactly. For integers,
//   floor((G*cur - A*prev + 2^23) / 2^24) = 64 P2 + floor((P1 + (P0 >> 15) + 2^8) / 2^9)
// (nested floor divisions, arithmetic shifts): vsra adds P0 >> 15 to P1 (the sum stays inside
// int32) and the rounding shift vrshr by 9 adds the 2^8 without overflow. That is exactly the
// portable loop's `value`; the P2 term is left out when G and A are below 2^30 (g < 64).
// vqmovun (signed to unsigned saturating narrow) is the clamp. Counts: a value outside
// [0, 65535] has a bit set above bit 15; the values of a block of steps are OR-ed and tested
// once, and only a block where that fires counts its kept values lane by lane.
struct NeonDigits {
  uint16x4_t low;   // g0, g1, a0, a1
  uint16x4_t wide;  // 64 g2, 64 a2, 0, 0
};

inline NeonDigits neon_digits(CorrectorCoefficients c) {
  constexpr std::uint32_t kDigit = (1u << 15) - 1;
  const std::uint32_t g = c.gain_q24, a = c.carry_q24;
  const std::uint16_t low[4] = {static_cast<std::uint16_t>(g & kDigit),
                                static_cast<std::uint16_t>((g >> 15) & kDigit),
                                static_cast<std::uint16_t>(a & kDigit),
                                static_cast<std::uint16_t>((a >> 15) & kDigit)};
  const std::uint16_t wide[4] = {static_cast<std::uint16_t>((g >> 30) << 6),
                                 static_cast<std::uint16_t>((a >> 30) << 6), 0, 0};
  return {vld1_u16(low), vld1_u16(wide)};
}

template <bool kWide>
inline __attribute__((always_inline)) int32x4_t neon_values(uint16x4_t cur, uint16x4_t prev,
                                                            const NeonDigits& d) {
  uint32x4_t p1 = vmull_lane_u16(cur, d.low, 1);
  p1 = vmlsl_lane_u16(p1, prev, d.low, 3);
  uint32x4_t p0 = vmull_lane_u16(cur, d.low, 0);
  p0 = vmlsl_lane_u16(p0, prev, d.low, 2);
  int32x4_t v =
      vrshrq_n_s32(vsraq_n_s32(vreinterpretq_s32_u32(p1), vreinterpretq_s32_u32(p0), 15), 9);
  if constexpr (kWide) {
    uint32x4_t w = vmlal_lane_u16(vreinterpretq_u32_s32(v), cur, d.wide, 0);
    v = vreinterpretq_s32_u32(vmlsl_lane_u16(w, prev, d.wide, 1));
  }
  return v;
}

// Steps per test: more steps spread the test's dependency chain (OR, narrow, move to a core
// register, branch), which an in-order core waits for; on aarch64 six (eight spill registers
// in the loop), on armv7 with its 16 Q registers four.
#if defined(__aarch64__)
constexpr std::size_t kNeonBlockSteps = 6;
#else
constexpr std::size_t kNeonBlockSteps = 4;
#endif

inline bool neon_any_above16(uint32x4_t bits) {
  return vget_lane_u64(vreinterpret_u64_u16(vshrn_n_u32(bits, 16)), 0) != 0;
}

// The counts of a block's kept values. Out of line: the (rare) counting stays out of the loop,
// which scripts/board-cost.sh reads as one straight block.
__attribute__((noinline, cold)) void neon_count(const int32x4_t* values, std::size_t count,
                                                std::uint32_t& n_low, std::uint32_t& n_high) {
  for (std::size_t i = 0; i < count; ++i) {
    std::int32_t lanes[4];
    vst1q_s32(lanes, values[i]);
    for (std::int32_t value : lanes) {
      n_low += value < 0 ? 1u : 0u;
      n_high += value > kMaxOut ? 1u : 0u;
    }
  }
}

// noinline: one symbol per variant, so scripts/board-cost.sh finds each loop the compiler emits.
template <bool kStore, bool kWide>
__attribute__((noinline)) void correct_neon_loop(const Pixel* __restrict current,
                                                 Pixel* __restrict previous,
                                                 CorrectorCoefficients c, Pixel* __restrict out,
                                                 std::size_t width, std::uint32_t& low,
                                                 std::uint32_t& high) {
  const NeonDigits d = neon_digits(c);
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  std::size_t x = 0;
  for (; x + 8 * kNeonBlockSteps <= width; x += 8 * kNeonBlockSteps) {
    constexpr std::size_t kValues = 2 * kNeonBlockSteps;
    int32x4_t values[kValues];
    for (std::size_t s = 0; s < kNeonBlockSteps; ++s) {
      const std::size_t at = x + 8 * s;
      const uint16x8_t cur = vld1q_u16(current + at);
      const uint16x8_t prev = vld1q_u16(previous + at);
      if constexpr (kStore) vst1q_u16(previous + at, cur);
      const int32x4_t lo = neon_values<kWide>(vget_low_u16(cur), vget_low_u16(prev), d);
      const int32x4_t hi = neon_values<kWide>(vget_high_u16(cur), vget_high_u16(prev), d);
      vst1q_u16(out + at, vcombine_u16(vqmovun_s32(lo), vqmovun_s32(hi)));
      values[2 * s] = lo;
      values[2 * s + 1] = hi;
    }
    // The block's values OR-ed as a tree: a chain of kValues dependent ORs would stall an
    // in-order core at every block's end.
    uint32x4_t bits[kValues / 2];
    for (std::size_t i = 0; i < kValues / 2; ++i)
      bits[i] = vreinterpretq_u32_s32(vorrq_s32(values[2 * i], values[2 * i + 1]));
    for (std::size_t n = kValues / 2; n > 1; n = (n + 1) / 2)  // fold the upper half down
      for (std::size_t i = 0; i < n / 2; ++i) bits[i] = vorrq_u32(bits[i], bits[n - 1 - i]);
    if (neon_any_above16(bits[0])) [[unlikely]] {
      // A copy made only here: handing `values` itself to the call would keep it in memory,
      // stored on every block.
      int32x4_t kept[kValues];
      for (std::size_t i = 0; i < kValues; ++i) kept[i] = values[i];
      neon_count(kept, kValues, n_low, n_high);
    }
  }
  for (; x + 8 <= width; x += 8) {  // the steps left over from blocks, tested one by one
    const uint16x8_t cur = vld1q_u16(current + x);
    const uint16x8_t prev = vld1q_u16(previous + x);
    if constexpr (kStore) vst1q_u16(previous + x, cur);
    const int32x4_t kept[2] = {neon_values<kWide>(vget_low_u16(cur), vget_low_u16(prev), d),
                               neon_values<kWide>(vget_high_u16(cur), vget_high_u16(prev), d)};
    vst1q_u16(out + x, vcombine_u16(vqmovun_s32(kept[0]), vqmovun_s32(kept[1])));
    if (neon_any_above16(vreinterpretq_u32_s32(vorrq_s32(kept[0], kept[1])))) [[unlikely]]
      neon_count(kept, 2, n_low, n_high);
  }
  low += n_low;
  high += n_high;
  correct_portable<kStore>(current + x, previous + x, c, out + x, width - x, low, high);
}

template <bool kStore>
void correct_neon(const Pixel* __restrict current, Pixel* __restrict previous,
                  CorrectorCoefficients c, Pixel* __restrict out, std::size_t width,
                  std::uint32_t& low, std::uint32_t& high) {
  if ((c.gain_q24 | c.carry_q24) >> 30 != 0)
    correct_neon_loop<kStore, true>(current, previous, c, out, width, low, high);
  else
    correct_neon_loop<kStore, false>(current, previous, c, out, width, low, high);
}

void correct_line_neon(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                       Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  // kStore = false never writes through the pointer.
  correct_neon<false>(current, const_cast<Pixel*>(previous), c, out, width, low, high);
}
void correct_update_neon(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                         Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  correct_neon<true>(current, previous, c, out, width, low, high);
}
#endif  // BOLO_NEON_KERNELS

struct Kernels {
  detail::KernelPath path;
  detail::CorrectLineFn correct;
  detail::CorrectUpdateFn update;
};

#if BOLO_X86_KERNELS
Kernels select_kernels() {
  if (cpu_has(detail::KernelPath::avx512_vnni))
    return {detail::KernelPath::avx512_vnni, correct_line_avx512_vnni, correct_update_avx512_vnni};
  if (cpu_has(detail::KernelPath::avx512))
    return {detail::KernelPath::avx512, correct_line_avx512, correct_update_avx512};
  if (cpu_has(detail::KernelPath::avx2))
    return {detail::KernelPath::avx2, correct_line_avx2, correct_update_avx2};
  return {detail::KernelPath::portable, correct_line_portable, correct_update_portable};
}

const Kernels& kernels() {
  static const Kernels chosen = select_kernels();  // once; no allocation
  return chosen;
}
#else
// Chosen at build time: a constant, no guarded static (a board program needs no C++ runtime).
#if BOLO_NEON_KERNELS
constexpr Kernels kBuildKernels{detail::KernelPath::neon, correct_line_neon, correct_update_neon};
#else
constexpr Kernels kBuildKernels{detail::KernelPath::portable, correct_line_portable,
                                correct_update_portable};
#endif
constexpr const Kernels& kernels() { return kBuildKernels; }
#endif

}  // namespace

void correct_line(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                  Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  kernels().correct(current, previous, c, out, width, low, high);
}

void correct_line_update(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                         Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high) {
  kernels().update(current, previous, c, out, width, low, high);
}

BOLO_KERNEL_CLONES
void scale_line(const Pixel* __restrict current, std::uint32_t gain_q24, Pixel* __restrict out,
                std::size_t width, std::uint32_t& high) {
  const std::uint64_t gain = gain_q24;
  std::uint32_t n_high = 0;
  for (std::size_t x = 0; x < width; ++x) {
    const std::uint64_t value = (current[x] * gain + kHalf) >> kShift;  // < 2^24
    n_high += value > kMaxOut ? 1u : 0u;
    out[x] = static_cast<Pixel>(value > kMaxOut ? kMaxOut : value);
  }
  high += n_high;
}

namespace detail {

const char* to_string(KernelPath path) {
  switch (path) {
    case KernelPath::portable: return "portable";
    case KernelPath::avx2: return "avx2";
    case KernelPath::avx512: return "avx512";
    case KernelPath::avx512_vnni: return "avx512_vnni";
    case KernelPath::neon: return "neon";
  }
  return "unknown";
}

bool kernel_path_available(KernelPath path) {
#if BOLO_X86_KERNELS
  return cpu_has(path);
#elif BOLO_NEON_KERNELS
  return path == KernelPath::portable || path == KernelPath::neon;
#else
  return path == KernelPath::portable;
#endif
}

KernelPath selected_kernel_path() { return kernels().path; }

CorrectLineFn correct_line_kernel(KernelPath path) {
  if (!kernel_path_available(path)) return nullptr;
  switch (path) {
    case KernelPath::portable: return correct_line_portable;
#if BOLO_X86_KERNELS
    case KernelPath::avx2: return correct_line_avx2;
    case KernelPath::avx512: return correct_line_avx512;
    case KernelPath::avx512_vnni: return correct_line_avx512_vnni;
#endif
#if BOLO_NEON_KERNELS
    case KernelPath::neon: return correct_line_neon;
#endif
    default: break;
  }
  return nullptr;
}

CorrectUpdateFn correct_update_kernel(KernelPath path) {
  if (!kernel_path_available(path)) return nullptr;
  switch (path) {
    case KernelPath::portable: return correct_update_portable;
#if BOLO_X86_KERNELS
    case KernelPath::avx2: return correct_update_avx2;
    case KernelPath::avx512: return correct_update_avx512;
    case KernelPath::avx512_vnni: return correct_update_avx512_vnni;
#endif
#if BOLO_NEON_KERNELS
    case KernelPath::neon: return correct_update_neon;
#endif
    default: break;
  }
  return nullptr;
}

}  // namespace detail
}  // namespace bolo::fw
