// The bad-pixel stage's intake of a line (see detail::IngestLine): copy or NUC into the ring and
// flag. The C++ loops are the definition, compiled as clones for the x86-64 levels; on x86-64 with
// GCC an AVX-512 version, tested against them (tests/firmware/test_ingest.cpp), is picked at run
// time; on ARM with NEON a NEON version, tested the same way, is chosen at build time.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "bolo/firmware/detail/kernels.hpp"
#include "bolo/firmware/nuc_stage.hpp"
#include "simd_intrinsics.hpp"

#if BOLO_NEON_KERNELS
#include "neon_nuc.hpp"
#endif

namespace bolo::fw::detail {
namespace {

// Eight flag bytes (0 or 1) in memory order -> bits 0..7. The multiply moves byte i's bit to bit
// 56 + i, every other partial product to a distinct lower or discarded bit, so nothing carries.
inline std::uint32_t pack_flag_bytes(const std::uint8_t* bytes) {
  std::uint64_t word;
  std::memcpy(&word, bytes, sizeof word);
  if constexpr (std::endian::native == std::endian::big) word = __builtin_bswap64(word);
  return static_cast<std::uint32_t>((word * 0x0102040810204080ull) >> 56);
}

// The mask bits of a flag word's 32 pixels (bits past the width are 0 by construction).
inline std::uint32_t load_flag_word(const std::uint8_t* bytes) {
  std::uint32_t word;
  std::memcpy(&word, bytes, sizeof word);
  return word;
}

// `n` <= 32 pixels from `x`: values into the ring, stuck flags as bytes into a local block (a
// loop the compiler vectorises; with n = 32 a constant), then packed to a word with the mask's.
template <bool kNuc, bool kStuck, bool kMask>
inline __attribute__((always_inline)) std::uint32_t ingest_block(
    const Pixel* __restrict in, const std::uint16_t* __restrict gain,
    const std::int16_t* __restrict offset, const std::uint8_t* __restrict mask_bits,
    Pixel stuck_low, Pixel stuck_high, Pixel* __restrict ring, std::size_t n) {
  std::uint8_t f[32] = {};
  for (std::size_t i = 0; i < n; ++i) {
    Pixel v = in[i];
    if constexpr (kNuc) v = nuc_pixel(v, gain[i], offset[i]);
    ring[i] = v;
    if constexpr (kStuck) f[i] = static_cast<std::uint8_t>((v == stuck_low) | (v == stuck_high));
  }
  std::uint32_t bits = 0;
  if constexpr (kStuck)
    bits = pack_flag_bytes(f) | pack_flag_bytes(f + 8) << 8 | pack_flag_bytes(f + 16) << 16 |
           pack_flag_bytes(f + 24) << 24;
  if constexpr (kMask) bits |= load_flag_word(mask_bits);
  return bits;
}

// One loop per configuration so each vectorises: no per-pixel tests of the configuration, no
// reloads of it through the aliasing `Pixel*` stores. Flags are gathered 32 to a word.
template <bool kNuc, bool kStuck, bool kMask>
inline __attribute__((always_inline)) bool ingest_loop(
    const Pixel* __restrict in, const std::uint16_t* __restrict gain,
    const std::int16_t* __restrict offset, const std::uint8_t* __restrict mask_bits,
    Pixel stuck_low, Pixel stuck_high, Pixel* __restrict ring, std::uint8_t* __restrict flag_bits,
    std::size_t width) {
  std::uint32_t any = 0;
  for (std::size_t base = 0; base < width; base += 32) {
    const std::size_t n = width - base < 32 ? width - base : 32;
    const std::uint16_t* g = kNuc ? gain + base : nullptr;
    const std::int16_t* o = kNuc ? offset + base : nullptr;
    const std::uint8_t* m = kMask ? mask_bits + base / 8 : nullptr;
    const std::uint32_t bits =
        n == 32 ? ingest_block<kNuc, kStuck, kMask>(in + base, g, o, m, stuck_low, stuck_high,
                                                    ring + base, 32)
                : ingest_block<kNuc, kStuck, kMask>(in + base, g, o, m, stuck_low, stuck_high,
                                                    ring + base, n);
    std::memcpy(flag_bits + base / 8, &bits, sizeof bits);
    any |= bits;
  }
  return any != 0;
}

template <bool kNuc>
inline __attribute__((always_inline)) bool ingest_any(const IngestLine& j) {
  if (j.detect_stuck && j.mask_bits != nullptr)
    return ingest_loop<kNuc, true, true>(j.in, j.gain_q14, j.offset, j.mask_bits, j.stuck_low,
                                         j.stuck_high, j.ring, j.flag_bits, j.width);
  if (j.detect_stuck)
    return ingest_loop<kNuc, true, false>(j.in, j.gain_q14, j.offset, j.mask_bits, j.stuck_low,
                                          j.stuck_high, j.ring, j.flag_bits, j.width);
  if (j.mask_bits != nullptr)
    return ingest_loop<kNuc, false, true>(j.in, j.gain_q14, j.offset, j.mask_bits, j.stuck_low,
                                          j.stuck_high, j.ring, j.flag_bits, j.width);
  return ingest_loop<kNuc, false, false>(j.in, j.gain_q14, j.offset, j.mask_bits, j.stuck_low,
                                         j.stuck_high, j.ring, j.flag_bits, j.width);
}

BOLO_KERNEL_CLONES
bool ingest_portable(const IngestLine& job) {
  return job.gain_q14 != nullptr ? ingest_any<true>(job) : ingest_any<false>(job);
}

// Line i of a run: its input, table, ring, flag and mask pointers (see detail::IngestRowsFn).
inline IngestLine run_line(const IngestLine& first, std::size_t i, std::size_t in_stride) {
  IngestLine j = first;
  const std::size_t at = i * first.width;
  const std::size_t flag_at = i * flag_line_bytes(first.width);
  j.in += i * in_stride;
  if (j.gain_q14 != nullptr) {
    j.gain_q14 += at;
    j.offset += at;
  }
  if (j.mask_bits != nullptr) j.mask_bits += flag_at;
  j.ring += at;
  j.flag_bits += flag_at;
  return j;
}

BOLO_KERNEL_CLONES
std::uint64_t ingest_rows_portable(const IngestLine& first, std::size_t rows,
                                   std::size_t in_stride) {
  std::uint64_t any = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    const IngestLine j = run_line(first, i, in_stride);
    const bool flagged = j.gain_q14 != nullptr ? ingest_any<true>(j) : ingest_any<false>(j);
    any |= std::uint64_t{flagged} << i;
  }
  return any;
}

#if BOLO_NEON_KERNELS
// ---- NEON: blocks of 32 pixels (one flag word), 8 pixels per step ----
// The NUC as in nuc_line's NEON version (neon_nuc.hpp): a line in 16-bit lanes, done again in
// 32-bit lanes when a pixel or gain is outside that case's range. Stuck flags are lane masks,
// narrowed to bytes, weighted by their bit (1, 2, ..., 128) and summed pairwise into the word.
// On aarch64 two words per iteration, packed together, so that an in-order core has more
// independent work to issue while flags are packed (armv7's 16 Q registers hold one word's
// inputs). The last width % 32 pixels: the portable block.
#if defined(__aarch64__)
constexpr std::size_t kNeonIngestWords = 2;
#else
constexpr std::size_t kNeonIngestWords = 1;
#endif

// The flag words of kWords (1 or 2) words of lane masks, word w in bits 32 w ... 32 w + 31.
template <std::size_t kWords>
inline std::uint64_t neon_flag_words(const uint16x8_t (&masks)[4 * kWords]) {
  static constexpr std::uint8_t kWeights[16] = {1, 2, 4, 8, 16, 32, 64, 128,
                                                1, 2, 4, 8, 16, 32, 64, 128};
#if defined(__aarch64__)
  // uzp1 keeps the low byte of each 16-bit mask: a word's pixels 0..15 and 16..31 as bytes.
  const uint8x16_t weights = vld1q_u8(kWeights);
  uint8x16_t pairs[kWords];
  for (std::size_t w = 0; w < kWords; ++w) {
    const uint8x16_t b01 = vandq_u8(vuzp1q_u8(vreinterpretq_u8_u16(masks[4 * w]),
                                              vreinterpretq_u8_u16(masks[4 * w + 1])),
                                    weights);
    const uint8x16_t b23 = vandq_u8(vuzp1q_u8(vreinterpretq_u8_u16(masks[4 * w + 2]),
                                              vreinterpretq_u8_u16(masks[4 * w + 3])),
                                    weights);
    pairs[w] = vpaddq_u8(b01, b23);  // sums of pixel pairs
  }
  // quads (word 0's in bytes 0..7, word 1's in 8..15), then each word's four bytes
  const uint8x16_t quads = vpaddq_u8(pairs[0], pairs[kWords - 1]);
  return vgetq_lane_u64(vreinterpretq_u64_u8(vpaddq_u8(quads, quads)), 0);
#else
  const uint8x8_t weights = vld1_u8(kWeights);
  uint8x8_t quads[kWords];
  for (std::size_t w = 0; w < kWords; ++w) {
    uint8x8_t b[4];
    for (std::size_t k = 0; k < 4; ++k) b[k] = vand_u8(vmovn_u16(masks[4 * w + k]), weights);
    quads[w] = vpadd_u8(vpadd_u8(b[0], b[1]), vpadd_u8(b[2], b[3]));  // pairs, then quads
  }
  return vget_lane_u64(vreinterpret_u64_u8(vpadd_u8(quads[0], quads[kWords - 1])), 0);
#endif
}

// The line's pointers, restrict-qualified: without it every ring or flag store could alias the
// next loads, and an in-order core would wait for each step in turn.
struct NeonIngestPointers {
  const Pixel* __restrict in;
  const std::uint16_t* __restrict gain;
  const std::int16_t* __restrict offset;
  const std::uint8_t* __restrict mask_bits;
  Pixel* __restrict ring;
  std::uint8_t* __restrict flag_bits;
};

// Words of 32 pixels from base (kWords: 1 or 2): values into the ring, flags stored; returns
// whether one was set. Every load first, then the arithmetic and the stores.
template <bool kNuc, bool kStuck, bool kMask, bool kNarrow, std::size_t kWords>
inline __attribute__((always_inline)) bool ingest_neon_words(const NeonIngestPointers& p,
                                                             std::size_t base, uint16x8_t low,
                                                             uint16x8_t high,
                                                             uint16x8_t& in_range) {
  constexpr std::size_t kSteps = 4 * kWords;
  uint16x8_t v[kSteps], g[kSteps];
  int16x8_t o[kSteps];
  for (std::size_t s = 0; s < kSteps; ++s) {
    v[s] = vld1q_u16(p.in + base + 8 * s);
    if constexpr (kNuc) {
      g[s] = vld1q_u16(p.gain + base + 8 * s);
      o[s] = vld1q_s16(p.offset + base + 8 * s);
    }
  }
  std::uint64_t bits = 0;  // word w in bits 32 w ...
  if constexpr (kMask) {
    bits = load_flag_word(p.mask_bits + base / 8);
    if constexpr (kWords == 2)
      bits |= std::uint64_t{load_flag_word(p.mask_bits + base / 8 + 4)} << 32;
  }
  uint16x8_t masks[kSteps], range[kSteps];
  for (std::size_t s = 0; s < kSteps; ++s) {
    if constexpr (kNuc)
      v[s] = kNarrow ? neon::nuc_narrow(v[s], g[s], o[s], range[s])
                     : neon::nuc_wide(v[s], g[s], o[s]);
    vst1q_u16(p.ring + base + 8 * s, v[s]);
    if constexpr (kStuck) masks[s] = vorrq_u16(vceqq_u16(v[s], low), vceqq_u16(v[s], high));
  }
  if constexpr (kNuc && kNarrow) {  // a tree, not a chain of kSteps dependent ORs
    for (std::size_t half = kSteps / 2; half > 0; half /= 2)
      for (std::size_t s = 0; s < half; ++s) range[s] = vorrq_u16(range[s], range[s + half]);
    in_range = vorrq_u16(in_range, range[0]);
  }
  if constexpr (kStuck) bits |= neon_flag_words<kWords>(masks);
  if constexpr (kWords == 2) {
    std::memcpy(p.flag_bits + base / 8, &bits, sizeof bits);  // little-endian: word 0 first
    return bits != 0;
  }
  const std::uint32_t word = static_cast<std::uint32_t>(bits);
  std::memcpy(p.flag_bits + base / 8, &word, sizeof word);
  return word != 0;
}

// One line; false when kNarrow met a pixel or gain outside its range (the line is then redone).
// noinline: one symbol per configuration, so scripts/board-cost.sh finds each loop.
template <bool kNuc, bool kStuck, bool kMask, bool kNarrow>
__attribute__((noinline)) bool ingest_neon_pass(const IngestLine& j, bool& any) {
  const NeonIngestPointers p{j.in, j.gain_q14, j.offset, j.mask_bits, j.ring, j.flag_bits};
  const uint16x8_t low = vdupq_n_u16(j.stuck_low);
  const uint16x8_t high = vdupq_n_u16(j.stuck_high);
  const std::size_t width = j.width;
  uint16x8_t in_range = vdupq_n_u16(0);
  std::uint32_t flagged = 0;
  std::size_t base = 0;
  for (; base + 32 * kNeonIngestWords <= width; base += 32 * kNeonIngestWords)
    flagged |= ingest_neon_words<kNuc, kStuck, kMask, kNarrow, kNeonIngestWords>(
                   p, base, low, high, in_range)
                   ? 1u
                   : 0u;
  if (base + 32 <= width) {
    flagged |=
        ingest_neon_words<kNuc, kStuck, kMask, kNarrow, 1>(p, base, low, high, in_range) ? 1u : 0u;
    base += 32;
  }
  if (kNuc && kNarrow && neon::narrow_out_of_range(in_range)) return false;
  if (base < width) {
    const std::size_t n = width - base;
    const std::uint32_t bits = ingest_block<kNuc, kStuck, kMask>(
        p.in + base, kNuc ? p.gain + base : nullptr, kNuc ? p.offset + base : nullptr,
        kMask ? p.mask_bits + base / 8 : nullptr, j.stuck_low, j.stuck_high, p.ring + base, n);
    std::memcpy(p.flag_bits + base / 8, &bits, sizeof bits);
    flagged |= bits;
  }
  any = flagged != 0;
  return true;
}

template <bool kNuc, bool kStuck, bool kMask>
inline __attribute__((always_inline)) bool ingest_neon_line(const IngestLine& j) {
  bool any = false;
  if (!ingest_neon_pass<kNuc, kStuck, kMask, true>(j, any)) [[unlikely]]
    ingest_neon_pass<kNuc, kStuck, kMask, false>(j, any);
  return any;
}

template <bool kNuc>
inline __attribute__((always_inline)) bool ingest_neon_any(const IngestLine& j) {
  if (j.detect_stuck)
    return j.mask_bits != nullptr ? ingest_neon_line<kNuc, true, true>(j)
                                  : ingest_neon_line<kNuc, true, false>(j);
  return j.mask_bits != nullptr ? ingest_neon_line<kNuc, false, true>(j)
                                : ingest_neon_line<kNuc, false, false>(j);
}

bool ingest_neon(const IngestLine& job) {
  return job.gain_q14 != nullptr ? ingest_neon_any<true>(job) : ingest_neon_any<false>(job);
}

std::uint64_t ingest_rows_neon(const IngestLine& first, std::size_t rows, std::size_t in_stride) {
  std::uint64_t any = 0;
  for (std::size_t i = 0; i < rows; ++i)
    any |= std::uint64_t{ingest_neon(run_line(first, i, in_stride))} << i;
  return any;
}
#endif  // BOLO_NEON_KERNELS

#if BOLO_X86_KERNELS
#define BOLO_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,avx2")))

// NUC, general case: mulhi/mullo give the u32 product in*gain as two halves; unpacklo/hi_epi16
// assemble it in 32-bit lanes (pixels 8j+0..3 and 8j+4..7 of each 128-bit lane), the offset is
// sign-extended the same way, and packus_epi32 (within 128-bit lanes again) restores pixel
// order while saturating the int32 sum to [0, 65535]: exactly nuc_pixel's clamp. in*gain + 2^13
// < 2^32, so the logical shift is exact. The usual case (pixels below 2^14, gains below 2.0) stays
// in 16-bit lanes: see nuc_avx512_narrow.
struct Avx512IngestConstants {
  __m512i half, low, high, flip;
  __mmask32 stuck_on;
};

// The general case: the u32 product and the offset in 32-bit lanes (see above).
BOLO_AVX512 inline __attribute__((always_inline)) __m512i nuc_avx512_wide(
    __m512i v, __m512i g, __m512i o, const Avx512IngestConstants& k) {
  const __m512i hi = _mm512_mulhi_epu16(v, g);
  const __m512i lo = _mm512_mullo_epi16(v, g);
  const __m512i sign = _mm512_srai_epi16(o, 15);
  const __m512i v0 = _mm512_add_epi32(
      _mm512_srli_epi32(_mm512_add_epi32(_mm512_unpacklo_epi16(lo, hi), k.half),
                        kNucGainFractionBits),
      _mm512_unpacklo_epi16(o, sign));
  const __m512i v1 = _mm512_add_epi32(
      _mm512_srli_epi32(_mm512_add_epi32(_mm512_unpackhi_epi16(lo, hi), k.half),
                        kNucGainFractionBits),
      _mm512_unpackhi_epi16(o, sign));
  return _mm512_packus_epi32(v0, v1);
}

// The usual case in 16-bit lanes, valid when the pixel is below 2^14 and the gain below 2^15
// (Q2.14 gains under 2.0); `in2` is 2 in. Then 2 in and gain are non-negative int16 and mulhrs
// gives (2 in * gain + 2^14) >> 15 = (in * gain + 2^13) >> 14, exactly nuc_pixel's `scaled`, at
// most 32767. Biased by -32768 (bit 15 flipped) it is in [-32768, -1]; a signed saturating add
// of the offset is then exactly the clamp to [0, 65535] once the bias is flipped back (the sum
// cannot exceed 32766, and everything at or below -32768 is 0).
BOLO_AVX512 inline __attribute__((always_inline)) __m512i nuc_avx512_narrow(
    __m512i in2, __m512i g, __m512i o, const Avx512IngestConstants& k) {
  const __m512i scaled = _mm512_mulhrs_epi16(in2, g);
  return _mm512_xor_si512(_mm512_adds_epi16(_mm512_xor_si512(scaled, k.flip), o), k.flip);
}

// One line's pointers, stepped along a run of lines.
struct IngestCursor {
  const Pixel* in;
  const std::uint16_t* gain;
  const std::int16_t* offset;
  const std::uint8_t* mask_bits;
  Pixel* ring;
  std::uint8_t* flag_bits;
};

// With IngestLine::prefetch: how far ahead of a step its input and table lines are asked for. It
// pays where the tables and input stream from L3 or DRAM; where they sit in L2 the extra
// instructions cost more than they save, which is why it is a hint the stage sets for large
// frames only (docs/benchmarks.md).
constexpr std::size_t kPrefetchPixels = 2048;

// Asks for the line kPrefetchPixels elements past `p`. The address is computed as an integer: it
// may lie past the array's end, where pointer arithmetic would be undefined; a prefetch of any
// address is harmless (it never faults).
template <class T>
BOLO_AVX512 inline __attribute__((always_inline)) void prefetch_ahead(const T* p) {
  const std::uintptr_t ahead = reinterpret_cast<std::uintptr_t>(p) + kPrefetchPixels * sizeof(T);
  _mm_prefetch(reinterpret_cast<const char*>(ahead), _MM_HINT_T0);
}

// How a step computes the NUC:
//   kNarrow:  always in 16-bit lanes, and bit 15 of `out_of_range` records (for the whole line)
//             whether some pixel or gain was outside that case's range: then the line is done
//             again with kChecked.
//   kChecked: per step, 16-bit lanes where the step is in range, 32-bit lanes otherwise.
enum class NucLanes : std::uint8_t { kNarrow, kChecked };

// 32 pixels from x; `kTail`: only those selected by `m` exist (masked loads and stores).
// Returns the step's flags (also stored).
template <bool kNuc, bool kMask, bool kTail, NucLanes kLanes, bool kPrefetch>
BOLO_AVX512 inline __attribute__((always_inline)) __mmask32 ingest_avx512_step(
    const IngestCursor& c, std::size_t x, __mmask32 m, const Avx512IngestConstants& k,
    __m512i& out_of_range) {
  if constexpr (kPrefetch) {
    prefetch_ahead(c.in + x);
    if constexpr (kNuc) {
      prefetch_ahead(c.gain + x);
      prefetch_ahead(c.offset + x);
    }
  }
  __m512i v = kTail ? _mm512_maskz_loadu_epi16(m, c.in + x) : _mm512_loadu_si512(c.in + x);
  if constexpr (kNuc) {
    const __m512i g =
        kTail ? _mm512_maskz_loadu_epi16(m, c.gain + x) : _mm512_loadu_si512(c.gain + x);
    const __m512i o =
        kTail ? _mm512_maskz_loadu_epi16(m, c.offset + x) : _mm512_loadu_si512(c.offset + x);
    if constexpr (kLanes == NucLanes::kNarrow) {
      // Unsigned saturating 2 in: exactly 2 in below 2^14, and bit 15 set for every in >= 2^14
      // (2^15..2^16-2, or 0xFFFF saturated). So bit 15 of in2 | gain is the range test, kept
      // across the line with one three-way OR per step instead of a test and branch per step.
      const __m512i in2 = _mm512_adds_epu16(v, v);
      out_of_range = _mm512_ternarylogic_epi32(out_of_range, in2, g, 0xFE);
      v = nuc_avx512_narrow(in2, g, o, k);
    } else {
      // bit 15 of in | 2 in | gain (2 in wraps for in >= 2^15, but then in's own bit 15 is set)
      const __m512i in2 = _mm512_add_epi16(v, v);
      if (_mm512_movepi16_mask(_mm512_ternarylogic_epi32(v, in2, g, 0xFE)) == 0) {
        v = nuc_avx512_narrow(in2, g, o, k);
      } else {
        v = nuc_avx512_wide(v, g, o, k);
      }
    }
  }
  if constexpr (kTail) {
    _mm512_mask_storeu_epi16(c.ring + x, m, v);
  } else {
    _mm512_storeu_si512(c.ring + x, v);
  }
  // Write-masked compares: only existing pixels, and none when stuck detection is off.
  const __mmask32 stuck_m = k.stuck_on & m;
  std::uint32_t bits = _cvtmask32_u32(_mm512_mask_cmpeq_epi16_mask(stuck_m, v, k.low) |
                                      _mm512_mask_cmpeq_epi16_mask(stuck_m, v, k.high));
  if constexpr (kMask) bits |= load_flag_word(c.mask_bits + x / 8);  // 0 past the width
  std::memcpy(c.flag_bits + x / 8, &bits, sizeof bits);
  return bits;
}

// One line; returns whether a pixel was flagged.
template <bool kNuc, bool kMask, NucLanes kLanes, bool kPrefetch>
BOLO_AVX512 inline __attribute__((always_inline)) bool ingest_avx512_line(
    const IngestCursor& c, std::size_t width, __mmask32 tail, const Avx512IngestConstants& k,
    __m512i& out_of_range) {
  std::uint32_t any = 0;
  std::size_t x = 0;
  for (; x + 32 <= width; x += 32)
    any |= ingest_avx512_step<kNuc, kMask, false, kLanes, kPrefetch>(c, x, ~__mmask32{0}, k,
                                                                     out_of_range);
  if (x < width)
    any |= ingest_avx512_step<kNuc, kMask, true, kLanes, false>(c, x, tail, k, out_of_range);
  return any != 0;
}

// `rows` lines from `first` (one for ingest_avx512); bit i of the result: line i has a flag.
// The constants are set up once per call, not once per line.
template <bool kNuc, bool kMask, bool kPrefetch>
BOLO_AVX512 std::uint64_t ingest_avx512_loop(const IngestLine& first, std::size_t rows,
                                             std::size_t in_stride) {
  const Avx512IngestConstants k{_mm512_set1_epi32(1 << (kNucGainFractionBits - 1)),
                                _mm512_set1_epi16(static_cast<short>(first.stuck_low)),
                                _mm512_set1_epi16(static_cast<short>(first.stuck_high)),
                                _mm512_set1_epi16(static_cast<short>(0x8000)),
                                first.detect_stuck ? ~__mmask32{0} : __mmask32{0}};
  const std::size_t width = first.width;
  const std::size_t flag_bytes = flag_line_bytes(width);
  const __mmask32 tail = static_cast<__mmask32>((std::uint32_t{1} << (width % 32)) - 1u);
  // A local cursor: the stores below cannot alias it, so no reloads.
  IngestCursor c{first.in, first.gain_q14, first.offset, first.mask_bits, first.ring,
                 first.flag_bits};
  std::uint64_t flagged_rows = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    __m512i out_of_range = _mm512_setzero_si512();
    bool any = ingest_avx512_line<kNuc, kMask, NucLanes::kNarrow, kPrefetch>(c, width, tail, k,
                                                                             out_of_range);
    if (kNuc && _mm512_movepi16_mask(out_of_range) != 0) [[unlikely]]
      any = ingest_avx512_line<kNuc, kMask, NucLanes::kChecked, false>(c, width, tail, k,
                                                                      out_of_range);
    flagged_rows |= std::uint64_t{any} << i;
    c.in += in_stride;
    if constexpr (kNuc) {
      c.gain += width;
      c.offset += width;
    }
    if constexpr (kMask) c.mask_bits += flag_bytes;
    c.ring += width;
    c.flag_bits += flag_bytes;
  }
  return flagged_rows;
}

template <bool kPrefetch>
BOLO_AVX512 std::uint64_t ingest_rows_avx512_hinted(const IngestLine& first, std::size_t rows,
                                                    std::size_t in_stride) {
  if (first.gain_q14 != nullptr)
    return first.mask_bits != nullptr
               ? ingest_avx512_loop<true, true, kPrefetch>(first, rows, in_stride)
               : ingest_avx512_loop<true, false, kPrefetch>(first, rows, in_stride);
  return first.mask_bits != nullptr
             ? ingest_avx512_loop<false, true, kPrefetch>(first, rows, in_stride)
             : ingest_avx512_loop<false, false, kPrefetch>(first, rows, in_stride);
}

BOLO_AVX512 std::uint64_t ingest_rows_avx512(const IngestLine& first, std::size_t rows,
                                             std::size_t in_stride) {
  return first.prefetch ? ingest_rows_avx512_hinted<true>(first, rows, in_stride)
                        : ingest_rows_avx512_hinted<false>(first, rows, in_stride);
}

BOLO_AVX512 bool ingest_avx512(const IngestLine& job) {
  return ingest_rows_avx512(job, 1, 0) != 0;
}
#endif  // BOLO_X86_KERNELS

#if BOLO_X86_KERNELS
IngestFn select_ingest() {
  return kernel_path_available(KernelPath::avx512) ? ingest_avx512 : ingest_portable;
}

IngestRowsFn select_ingest_rows() {
  return kernel_path_available(KernelPath::avx512) ? ingest_rows_avx512 : ingest_rows_portable;
}
#elif BOLO_NEON_KERNELS
// Chosen at build time: constants, no guarded statics (a board program needs no C++ runtime).
constexpr IngestFn kBuildIngest = ingest_neon;
constexpr IngestRowsFn kBuildIngestRows = ingest_rows_neon;
#else
constexpr IngestFn kBuildIngest = ingest_portable;
constexpr IngestRowsFn kBuildIngestRows = ingest_rows_portable;
#endif

}  // namespace

IngestFn ingest_kernel(KernelPath path) {
  if (!kernel_path_available(path)) return nullptr;
  switch (path) {
    case KernelPath::portable: return ingest_portable;
#if BOLO_X86_KERNELS
    case KernelPath::avx512: return ingest_avx512;
#endif
#if BOLO_NEON_KERNELS
    case KernelPath::neon: return ingest_neon;
#endif
    default: break;
  }
  return nullptr;
}

bool ingest_line(const IngestLine& job) {
#if BOLO_X86_KERNELS
  static const IngestFn chosen = select_ingest();  // once; no allocation
  return chosen(job);
#else
  return kBuildIngest(job);
#endif
}

}  // namespace bolo::fw::detail

namespace bolo::fw::detail {

IngestRowsFn ingest_rows_kernel(KernelPath path) {
  if (!kernel_path_available(path)) return nullptr;
  switch (path) {
    case KernelPath::portable: return ingest_rows_portable;
#if BOLO_X86_KERNELS
    case KernelPath::avx512: return ingest_rows_avx512;
#endif
#if BOLO_NEON_KERNELS
    case KernelPath::neon: return ingest_rows_neon;
#endif
    default: break;
  }
  return nullptr;
}

std::uint64_t ingest_rows(const IngestLine& first, std::size_t rows, std::size_t in_stride) {
#if BOLO_X86_KERNELS
  static const IngestRowsFn chosen = select_ingest_rows();  // once; no allocation
  return chosen(first, rows, in_stride);
#else
  return kBuildIngestRows(first, rows, in_stride);
#endif
}

void pack_mask_bits(const std::uint8_t* mask, std::size_t width, std::uint8_t* bits) {
  for (std::size_t base = 0; base < width; base += 32) {
    std::uint32_t word = 0;
    for (std::size_t i = 0; i < 32 && base + i < width; ++i)
      word |= std::uint32_t{mask[base + i] != 0} << i;
    std::memcpy(bits + base / 8, &word, sizeof word);
  }
}

}  // namespace bolo::fw::detail
