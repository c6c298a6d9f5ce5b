// The per-pixel kernels of the two-frame corrector. Written so the compiler vectorises them:
// unsigned 64-bit products of u16 x u32 (one pmuludq / umull per lane), a bias that keeps the
// difference non-negative so a logical shift does the rounding division, then 32-bit clamping.

#include <cstddef>
#include <cstdint>

#include "bolo/firmware/two_frame_corrector.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(BOLO_NO_MULTIVERSION)
// Same integer code built three times; the loader picks AVX-512 (x86-64-v4: 64-bit lanes with
// vpmullq, ~3x the AVX2 clone's rate, see docs/benchmarks.md) or AVX2 where the CPU has it.
// Bit-exact by construction: integer arithmetic has one answer.
#define BOLO_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define BOLO_KERNEL_CLONES
#endif

namespace bolo::fw {
namespace {

constexpr unsigned kShift = kCoefficientFractionBits;
constexpr std::uint64_t kHalf = std::uint64_t{1} << (kShift - 1);
// G * cur < 2^48 and A * prev < 2^48: adding 2^48 makes G*cur - A*prev + half non-negative.
constexpr std::uint64_t kBias = std::uint64_t{1} << 48;
constexpr std::int32_t kBiasShifted = std::int32_t{1} << (48 - kShift);
constexpr std::int32_t kMaxOut = 0xFFFF;

}  // namespace

BOLO_KERNEL_CLONES
void correct_line(const Pixel* __restrict current, const Pixel* __restrict previous,
                  CorrectorCoefficients c, Pixel* __restrict out, std::size_t width,
                  std::uint32_t& low, std::uint32_t& high) {
  const std::uint64_t gain = c.gain_q24;
  const std::uint64_t carry = c.carry_q24;
  std::uint32_t n_low = 0;
  std::uint32_t n_high = 0;
  for (std::size_t x = 0; x < width; ++x) {
    const std::uint64_t biased = current[x] * gain + (kBias + kHalf) - previous[x] * carry;
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

}  // namespace bolo::fw
