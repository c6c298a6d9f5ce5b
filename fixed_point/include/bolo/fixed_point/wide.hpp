#pragma once
// A 128-bit unsigned magnitude built from two uint64 halves, for exact 64 x 64 -> 128 products
// and their rounded shifts. Portable: armhf has no __int128.

#include <cstdint>

#include "bolo/fixed_point/rounding.hpp"

namespace bolo::fx::detail {

struct U128 {
  std::uint64_t hi = 0;
  std::uint64_t lo = 0;
};

constexpr bool is_zero(U128 x) { return x.hi == 0 && x.lo == 0; }

// The exact product, from four 32 x 32 -> 64 partial products.
constexpr U128 mul_64x64(std::uint64_t a, std::uint64_t b) {
  constexpr std::uint64_t kLow32 = 0xFFFF'FFFFu;
  const std::uint64_t a_lo = a & kLow32, a_hi = a >> 32;
  const std::uint64_t b_lo = b & kLow32, b_hi = b >> 32;
  const std::uint64_t ll = a_lo * b_lo;
  const std::uint64_t lh = a_lo * b_hi;
  const std::uint64_t hl = a_hi * b_lo;
  const std::uint64_t hh = a_hi * b_hi;
  const std::uint64_t mid = (ll >> 32) + (lh & kLow32) + (hl & kLow32);  // < 3 * 2^32
  return U128{hh + (lh >> 32) + (hl >> 32) + (mid >> 32), (mid << 32) | (ll & kLow32)};
}

// x >> s for any s (s >= 128 gives 0).
constexpr U128 shift_right(U128 x, unsigned s) {
  if (s == 0) return x;
  if (s >= 128) return U128{};
  if (s >= 64) return U128{0, x.hi >> (s - 64)};
  return U128{x.hi >> s, (x.lo >> s) | (x.hi << (64 - s))};
}

constexpr bool bit_is_set(U128 x, unsigned i) {  // i < 128
  return ((i >= 64 ? x.hi >> (i - 64) : x.lo >> i) & 1u) != 0;
}

constexpr bool any_bit_below(U128 x, unsigned i) {  // bits [0, i), i <= 128
  if (i == 0) return false;
  if (i >= 128) return !is_zero(x);
  if (i >= 64) return x.lo != 0 || (x.hi & ((std::uint64_t{1} << (i - 64)) - 1)) != 0;
  return (x.lo & ((std::uint64_t{1} << i) - 1)) != 0;
}

constexpr U128 increment(U128 x) {
  const std::uint64_t lo = x.lo + 1;
  return U128{lo == 0 ? x.hi + 1 : x.hi, lo};
}

// m / 2^s rounded, for the magnitude m of a value with the given sign; any s. Cannot overflow:
// for s >= 1 the truncated quotient is below 2^127.
constexpr U128 round_shift_right(U128 m, unsigned s, bool negative, Rounding r) {
  if (s == 0) return m;
  const U128 q = shift_right(m, s);
  const Discarded d = s > 128 ? (is_zero(m) ? Discarded::zero : Discarded::below_half)
                              : classify(bit_is_set(m, s - 1), any_bit_below(m, s - 1));
  return round_magnitude_up(r, negative, (q.lo & 1u) != 0, d) ? increment(q) : q;
}

}  // namespace bolo::fx::detail
