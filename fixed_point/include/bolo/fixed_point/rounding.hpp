#pragma once
// Rounded integer shifts and divisions, and saturation into a narrower integer type.
//
// Every function here is total: it is defined (no undefined behaviour, no trap) for every input,
// including shift counts of 64 and more, INT64_MIN / -1 and a zero divisor. Arguments outside
// the documented domain are programming errors: in a constant expression they fail to compile,
// at run time they give the value documented next to the function.
//
// Signed values are rounded through their magnitude: the quotient of |v| is rounded and the sign
// put back. That gives one rounding rule for signed and unsigned operands, needs no arithmetic
// shift of a negative value and cannot overflow (|INT64_MIN| = 2^63 fits a uint64).

#include <cstdint>
#include <limits>
#include <type_traits>

namespace bolo::fx {

enum class Rounding {
  nearest_away,  // to nearest; a tie (exactly .5) goes away from zero: 2.5 -> 3, -2.5 -> -3
  nearest_even,  // to nearest; a tie goes to the even neighbour: 2.5 -> 2, 3.5 -> 4, -2.5 -> -2
  floor,         // toward minus infinity: 2.7 -> 2, -2.2 -> -3
  toward_zero,   // truncation: 2.7 -> 2, -2.7 -> -2
};

// The project default: to nearest, ties away from zero.
//  * It is what std::round / std::lround do, so the double references in sim/ round exactly like
//    the firmware; fixed-vs-float tests then differ only by the coefficient error, never by a
//    rounding convention.
//  * It is symmetric: round(-x) == -round(x), so a correction treats signals above and below a
//    reference level alike (floor, the cheapest, biases every result by -1/2 LSB).
//  * On the non-negative values of the per-pixel kernels it is "add 2^(s-1), shift right", one
//    add and one shift, which is how firmware/ writes its hot loops.
// Its bias (ties only ever go up in magnitude) needs exact ties, which occur for 1 input in 2^s;
// nearest_even is there for long chains of roundings where that would accumulate.
inline constexpr Rounding kDefaultRounding = Rounding::nearest_away;

namespace detail {

// Called only on a failed precondition or a forbidden overflow. It is deliberately not constexpr:
// reaching it during constant evaluation makes the expression ill-formed, so the compiler
// reports the mistake and names this function in the message.
inline void precondition_failed_in_constant_expression() {}

constexpr void precondition_failed() {
  if (std::is_constant_evaluated()) precondition_failed_in_constant_expression();
}

// What a rounding discards, in units of the last kept digit.
enum class Discarded { zero, below_half, half, above_half };

// Whether the truncated magnitude must grow by one. `negative` is the sign of the exact value;
// `odd` is the parity of the truncated magnitude (the parity of the quotient itself).
constexpr bool round_magnitude_up(Rounding r, bool negative, bool odd, Discarded d) {
  if (d == Discarded::zero) return false;
  switch (r) {
    case Rounding::nearest_away: return d != Discarded::below_half;
    case Rounding::nearest_even: return d == Discarded::above_half || (d == Discarded::half && odd);
    case Rounding::floor: return negative;
    case Rounding::toward_zero: return false;
  }
  return false;
}

// Classifies a discarded part from its first bit ("round") and whether any later bit is set.
constexpr Discarded classify(bool round_bit, bool sticky) {
  if (round_bit) return sticky ? Discarded::above_half : Discarded::half;
  return sticky ? Discarded::below_half : Discarded::zero;
}

// The low `s` bits of v (s >= 1) as a fraction of 2^s.
constexpr Discarded discarded_low_bits(std::uint64_t v, unsigned s) {
  if (s > 64) return v == 0 ? Discarded::zero : Discarded::below_half;  // v < 2^64 <= 2^(s-1)
  const bool round_bit = ((v >> (s - 1)) & 1u) != 0;
  const std::uint64_t below_mask = (std::uint64_t{1} << (s - 1)) - 1;  // s - 1 <= 63
  return classify(round_bit, (v & below_mask) != 0);
}

// A remainder 0 <= r < den as a fraction of den (compares r with den - r: no overflow).
constexpr Discarded discarded_remainder(std::uint64_t r, std::uint64_t den) {
  if (r == 0) return Discarded::zero;
  const std::uint64_t rest = den - r;
  if (r < rest) return Discarded::below_half;
  return r == rest ? Discarded::half : Discarded::above_half;
}

// Rounded m / 2^s for a magnitude m of a value with the given sign. Never overflows: for s >= 1
// the truncated quotient is below 2^63, so adding one is safe.
constexpr std::uint64_t shift_magnitude(std::uint64_t m, unsigned s, bool negative, Rounding r) {
  if (s == 0) return m;
  const std::uint64_t q = s >= 64 ? 0 : m >> s;
  return q + (round_magnitude_up(r, negative, (q & 1u) != 0, discarded_low_bits(m, s)) ? 1u : 0u);
}

// |v| of a signed value as a uint64; exact for INT64_MIN (modular arithmetic, no overflow).
constexpr std::uint64_t magnitude(std::int64_t v) {
  const auto u = static_cast<std::uint64_t>(v);
  return v < 0 ? std::uint64_t{0} - u : u;
}

// -m or m as int64 for a magnitude m <= 2^63 (negative) or < 2^63 (non-negative).
constexpr std::int64_t apply_sign(std::uint64_t m, bool negative) {
  return static_cast<std::int64_t>(negative ? std::uint64_t{0} - m : m);
}

}  // namespace detail

// v / 2^s, rounded. Intended for s in [0, 62]; larger s are defined too (the rounded value of a
// number of magnitude <= 1/2).
template <Rounding R = kDefaultRounding>
constexpr std::int64_t shift_right(std::int64_t v, unsigned s) {
  const bool negative = v < 0;
  const std::uint64_t q = detail::shift_magnitude(detail::magnitude(v), s, negative, R);
  return detail::apply_sign(q, negative);
}

// v / 2^s, rounded. Intended for s in [0, 63]; s >= 64 gives the rounded value of v / 2^s < 1.
template <Rounding R = kDefaultRounding>
constexpr std::uint64_t shift_right(std::uint64_t v, unsigned s) {
  return detail::shift_magnitude(v, s, false, R);
}

// num / den, rounded. Precondition den > 0; den == 0 does not compile in a constant expression
// and gives 0 for 0 / 0 and UINT64_MAX otherwise at run time.
template <Rounding R = kDefaultRounding>
constexpr std::uint64_t divide(std::uint64_t num, std::uint64_t den) {
  if (den == 0) {
    detail::precondition_failed();
    return num == 0 ? 0 : std::numeric_limits<std::uint64_t>::max();
  }
  const std::uint64_t q = num / den;  // den >= 2 whenever rounding adds one, so q + 1 fits
  const detail::Discarded d = detail::discarded_remainder(num % den, den);
  return q + (detail::round_magnitude_up(R, false, (q & 1u) != 0, d) ? 1u : 0u);
}

// num / den, rounded. INT64_MIN / -1 saturates to INT64_MAX. Precondition den != 0; den == 0
// does not compile in a constant expression and gives 0, INT64_MAX or INT64_MIN (the sign of
// num) at run time.
template <Rounding R = kDefaultRounding>
constexpr std::int64_t divide(std::int64_t num, std::int64_t den) {
  if (den == 0) {
    detail::precondition_failed();
    if (num == 0) return 0;
    return num > 0 ? std::numeric_limits<std::int64_t>::max()
                   : std::numeric_limits<std::int64_t>::min();
  }
  const bool negative = (num < 0) != (den < 0);
  const std::uint64_t n = detail::magnitude(num);
  const std::uint64_t d = detail::magnitude(den);
  std::uint64_t q = n / d;  // <= 2^63, and d >= 2 whenever rounding adds one
  if (detail::round_magnitude_up(R, negative, (q & 1u) != 0,
                                 detail::discarded_remainder(n % d, d))) {
    ++q;
  }
  if (!negative && q > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    return std::numeric_limits<std::int64_t>::max();  // only INT64_MIN / -1
  }
  return detail::apply_sign(q, negative);
}

// v clamped into T's range. T is any integer type of up to 64 bits (int64 is the identity;
// uint64 clamps negative values to 0).
template <class T>
  requires std::is_integral_v<T>
constexpr T saturate(std::int64_t v) {
  constexpr T lo = std::numeric_limits<T>::min();
  constexpr T hi = std::numeric_limits<T>::max();
  if constexpr (std::is_signed_v<T>) {
    if (v < static_cast<std::int64_t>(lo)) return lo;
    if (v > static_cast<std::int64_t>(hi)) return hi;
  } else {
    if (v < 0) return lo;
    if (static_cast<std::uint64_t>(v) > static_cast<std::uint64_t>(hi)) return hi;
  }
  return static_cast<T>(v);
}

}  // namespace bolo::fx
