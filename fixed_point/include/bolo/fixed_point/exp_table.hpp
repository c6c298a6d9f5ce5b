#pragma once
// exp(-x) in fixed point from compile-time tables; integer-only at run time.
//
// x = k + j/256 + r with k = floor(x), j the next 8 bits and r < 2^-8 the last 16 bits of the
// Q8.24 input, so exp(-x) = exp(-k) * exp(-j/256) * exp(-r):
//   * exp(-k), k = 0..22, and exp(-j/256), j = 0..255: tables in Q0.63 (values <= 1, so <= 2^63),
//     generated at compile time in double;
//   * exp(-r): 1 - r + r^2/2 - r^3/6 + r^4/24 - r^5/120 in Q0.63 from exact integer powers of
//     the 16-bit remainder (the omitted r^6/720 < 2^-57 is 3e-8 units of the Q0.32 result);
//   * the three factors are multiplied 64 x 64 -> 128 and rounded back to Q0.63, and the
//     product is rounded once to Q0.32.
// The only sizeable error is that last rounding (1/2 unit); the tables and products add < 1e-5
// units. For x >= 23 the exact value is below 0.441 units, so 0 is the rounded result.
//
// Why double and not long double for the tables: the generator runs in constant evaluation, which
// follows the target's floating-point formats. double is IEEE binary64 on x86-64, aarch64 and
// armhf, so every target gets bit-identical tables; long double is 80-bit x87 on x86-64, binary128
// on aarch64 and plain binary64 on armhf, so tables built with it would differ by target. The
// extra precision is not needed either: a table entry off by a few ulp of a double changes the
// Q0.32 result by less than 1e-5 units.

#include <array>
#include <cstddef>
#include <cstdint>

#include "bolo/fixed_point/rounding.hpp"
#include "bolo/fixed_point/wide.hpp"

namespace bolo::fx {

namespace detail {

// exp(-x) for 0 <= x < 32, in double, for building tables at compile time only (consteval: it
// can never run on the board). 1 / sum(x^n / n!): the series of exp(+x) has only positive terms,
// so nothing cancels and the result is good to a few ulp.
consteval double exp_neg_for_table(double x) {
  double sum = 1.0;
  double term = 1.0;
  for (int n = 1; n < 200 && term > sum * 1e-20; ++n) {
    term *= x / n;
    sum += term;
  }
  return 1.0 / sum;
}

// v in [0, 1] to Q0.63, rounded to nearest (ties up). Not `(uint64)(v * 2^63 + 0.5)`: in
// [2^52, 2^53) doubles are spaced 1 apart, so `+ 0.5` is itself rounded (to even) and an odd
// integer came out one too high (exp(-7) did); splitting off the whole part is exact.
consteval std::uint64_t to_q63(double v) {
  const double scaled = v * 0x1p63;
  const auto whole = static_cast<std::uint64_t>(scaled);
  return whole + (scaled - static_cast<double>(whole) >= 0.5 ? 1u : 0u);
}

// round(a * b / 2^63) for Q0.63 factors <= 2^63 (so the result is <= 2^63).
constexpr std::uint64_t mul_q63(std::uint64_t a, std::uint64_t b) {
  return round_shift_right(mul_64x64(a, b), 63, false, Rounding::nearest_away).lo;
}

}  // namespace detail

// Inputs with x = x_q24 / 2^24 >= kExpNegCutoff give 0 (exp(-23) * 2^32 = 0.4407 < 1/2).
inline constexpr unsigned kExpNegCutoff = 23;

namespace detail {

// table[i] = exp(-i / Divisor) in Q0.63.
template <std::size_t N, unsigned Divisor>
consteval std::array<std::uint64_t, N> make_exp_neg_table() {
  std::array<std::uint64_t, N> table{};
  for (std::size_t i = 0; i < N; ++i) {
    table[i] = to_q63(exp_neg_for_table(static_cast<double>(i) / Divisor));
  }
  return table;
}

}  // namespace detail

// exp(-k) in Q0.63, k = 0..22.
inline constexpr std::array<std::uint64_t, kExpNegCutoff> kExpNegIntegerQ63 =
    detail::make_exp_neg_table<kExpNegCutoff, 1>();

// exp(-j / 256) in Q0.63, j = 0..255.
inline constexpr std::array<std::uint64_t, 256> kExpNegFractionQ63 =
    detail::make_exp_neg_table<256, 256>();

// exp(-x) for x = x_q24 / 2^24 (Q8.24, x in [0, 256)), returned in Q0.32 as a uint64 in
// [0, 2^32] (exp(0) = 2^32 exactly). Error <= 2 units of 2^-32 against the exact value
// (measured by tests/fixed_point: at most 0.500001). Integer-only at run time.
constexpr std::uint64_t exp_neg_q32(std::uint32_t x_q24) {
  const std::uint32_t k = x_q24 >> 24;
  if (k >= kExpNegCutoff) return 0;
  const std::uint32_t j = (x_q24 >> 16) & 0xFFu;
  // r = rem / 2^24 with rem < 2^16; the powers of rem are exact (rem^4 < 2^64).
  const std::uint64_t rem = x_q24 & 0xFFFFu;
  const std::uint64_t rem2 = rem * rem;
  const std::uint64_t rem3 = rem2 * rem;
  const std::uint64_t rem4 = rem3 * rem;
  // In Q0.63: r = rem * 2^39, r^2/2 = rem^2 * 2^14, r^3/6 = rem^3 / (6 * 2^9),
  // r^4/24 = rem^4 / (24 * 2^33), r^5/120 = (rem^4 / 2^16) * rem / (120 * 2^41).
  const std::uint64_t r5_term =
      divide(divide(rem4, std::uint64_t{1} << 16) * rem, std::uint64_t{120} << 41);
  const std::uint64_t exp_neg_r = (std::uint64_t{1} << 63) - (rem << 39) + (rem2 << 14) -
                                  divide(rem3, std::uint64_t{6} << 9) +
                                  divide(rem4, std::uint64_t{24} << 33) - r5_term;
  const std::uint64_t product = detail::mul_q63(
      detail::mul_q63(kExpNegIntegerQ63[k], kExpNegFractionQ63[j]), exp_neg_r);
  return shift_right(product, 31);
}

}  // namespace bolo::fx
