#pragma once
// Q<IntBits, FracBits, Signed>: a fixed-point number raw * 2^-FracBits.
//
//  * IntBits integer bits and FracBits fraction bits, both >= 0, not counting the sign bit:
//    Q<1, 14> is the classic signed Q1.14 (16 bits, [-2, 2)), Q<8, 24, false> is unsigned Q8.24
//    (32 bits, [0, 256)). IntBits + FracBits (+1 when Signed) <= 64.
//  * Storage is the smallest of (u)int8/16/32/64 that holds those bits. A format narrower than
//    its storage (Q<2, 4> in an int8) is still limited to its own range: every Q holds a value
//    of its format, from_raw() included.
//  * Range: signed [-2^IntBits, 2^IntBits - 2^-FracBits], unsigned [0, 2^IntBits - 2^-FracBits],
//    step epsilon() = 2^-FracBits.
//
// Saturation policy: nothing wraps. Every operation that can leave the destination's range clamps
// to the nearest rail (min() or max()); the conversions return Converted<Q>, which says whether
// they clamped. Overflow::checked additionally makes an overflow a compile error when the
// conversion is evaluated as a constant (for constants written as from_double(...)).
//
// Run-time arithmetic is integer-only. to_double() and from_double() are for tests, host tools
// and compile-time constants: the firmware never computes a run-time value through them.

#include <compare>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "bolo/fixed_point/rounding.hpp"
#include "bolo/fixed_point/storage.hpp"
#include "bolo/fixed_point/wide.hpp"

namespace bolo::fx {

enum class Overflow {
  saturate,  // clamp to the nearest rail; Converted::saturated reports it
  checked,   // overflow is a bug: ill-formed in a constant expression; at run time it still
             // clamps and reports, exactly like saturate (never UB, never wraps)
};

// The result of a conversion: the value (clamped when out of range) and whether it was clamped.
template <class QType>
struct Converted {
  QType value{};
  bool saturated = false;
};

template <int IntBits, int FracBits, bool Signed = true>
class Q;

namespace detail {

template <class T>
struct is_q : std::false_type {};
template <int I, int F, bool S>
struct is_q<Q<I, F, S>> : std::true_type {};

struct SignMagnitude {
  bool negative = false;
  std::uint64_t magnitude = 0;
};

template <class V>
  requires std::is_integral_v<V>
constexpr SignMagnitude sign_magnitude(V v) {
  if constexpr (std::is_signed_v<V>) {
    return {v < 0, magnitude(static_cast<std::int64_t>(v))};
  } else {
    return {false, static_cast<std::uint64_t>(v)};
  }
}

// 2^e as a double, exact for the exponents used here (|e| <= 128).
constexpr double pow2(int e) {
  double p = 1.0;
  for (; e > 0; --e) p *= 2.0;
  for (; e < 0; ++e) p *= 0.5;
  return p;
}

}  // namespace detail

template <class T>
concept QFormat = detail::is_q<T>::value;

template <int IntBits, int FracBits, bool Signed>
class Q {
  static_assert(IntBits >= 0, "IntBits must be >= 0");
  static_assert(FracBits >= 0, "FracBits must be >= 0");
  static_assert(IntBits + FracBits >= 1, "a format needs at least one integer or fraction bit");
  static_assert(IntBits + FracBits + (Signed ? 1 : 0) <= 64,
                "a format must fit 64 bits (sign bit included)");

 public:
  static constexpr int int_bits = IntBits;
  static constexpr int frac_bits = FracBits;
  static constexpr bool is_signed = Signed;
  static constexpr int value_bits = IntBits + FracBits;  // without the sign
  static constexpr int total_bits = value_bits + (Signed ? 1 : 0);
  using storage_type = detail::storage_t<total_bits, Signed>;

  static constexpr storage_type max_raw = static_cast<storage_type>(
      value_bits == 64 ? std::numeric_limits<std::uint64_t>::max()
                       : (std::uint64_t{1} << (value_bits % 64)) - 1);
  static constexpr storage_type min_raw =
      Signed ? static_cast<storage_type>(-static_cast<std::int64_t>(max_raw) - 1) : storage_type{0};

  constexpr Q() = default;  // zero

  // The value raw * 2^-FracBits; a raw value outside the format's range is clamped.
  template <class V>
    requires std::is_integral_v<V>
  static constexpr Q from_raw(V raw) {
    const detail::SignMagnitude v = detail::sign_magnitude(raw);
    return from_scaled(v.negative, detail::U128{0, v.magnitude}, FracBits).value;
  }

  constexpr storage_type raw() const { return raw_; }

  static constexpr Q min() { return Q(min_raw); }
  static constexpr Q max() { return Q(max_raw); }
  static constexpr Q epsilon() { return Q(storage_type{1}); }  // one LSB, 2^-FracBits

  // The integer v in this format (exact unless clamped).
  template <Overflow O = Overflow::saturate, class V>
    requires std::is_integral_v<V>
  static constexpr Converted<Q> from_int(V v) {
    const detail::SignMagnitude m = detail::sign_magnitude(v);
    return from_scaled<kDefaultRounding, O>(m.negative, detail::U128{0, m.magnitude}, 0);
  }

  // This value in another format, rounded (when To has fewer fraction bits) and clamped.
  template <class To, Rounding R = kDefaultRounding, Overflow O = Overflow::saturate>
    requires QFormat<To>
  constexpr Converted<To> convert() const {
    const detail::SignMagnitude m = detail::sign_magnitude(raw_);
    return To::template from_scaled<R, O>(m.negative, detail::U128{0, m.magnitude}, FracBits);
  }

  // A double in this format, rounded and clamped; NaN gives 0, reported as saturated. For
  // constants, tests and host code: `constexpr auto k = Q<1, 14>::from_double(0.7).value;`.
  template <Rounding R = kDefaultRounding, Overflow O = Overflow::saturate>
  static constexpr Converted<Q> from_double(double v) {
    if (v != v) {
      if constexpr (O == Overflow::checked) detail::precondition_failed();
      return {Q{}, true};
    }
    const bool negative = v < 0;
    // Scaling by a power of two is exact (an overflow to infinity saturates below anyway).
    const double scaled = (negative ? -v : v) * detail::pow2(FracBits);
    if (scaled >= 0x1p64) return from_scaled<R, O>(negative, detail::U128{1, 0}, FracBits);
    const auto whole = static_cast<std::uint64_t>(scaled);
    const double fraction = scaled - static_cast<double>(whole);  // exact
    const detail::Discarded d = fraction == 0.0  ? detail::Discarded::zero
                                : fraction < 0.5 ? detail::Discarded::below_half
                                : fraction == 0.5 ? detail::Discarded::half
                                                  : detail::Discarded::above_half;
    detail::U128 m{0, whole};
    if (detail::round_magnitude_up(R, negative, (whole & 1u) != 0, d)) m = detail::increment(m);
    return from_scaled<R, O>(negative, m, FracBits);
  }

  // For tests and host code only (a 64-bit raw value may round to the nearest double).
  constexpr double to_double() const {
    return static_cast<double>(raw_) * detail::pow2(-FracBits);
  }

  // The building block of every conversion: the value (negative ? -1 : 1) * magnitude * 2^-frac
  // rounded to this format's step and clamped to its range. `frac` >= 0; magnitude < 2^128.
  template <Rounding R = kDefaultRounding, Overflow O = Overflow::saturate>
  static constexpr Converted<Q> from_scaled(bool negative, detail::U128 magnitude, int frac) {
    const std::uint64_t limit = negative ? kNegativeLimit : kPositiveLimit;
    detail::U128 m = magnitude;
    bool overflow = false;
    if (frac > FracBits) {
      m = detail::round_shift_right(m, static_cast<unsigned>(frac - FracBits), negative, R);
      overflow = m.hi != 0 || m.lo > limit;
    } else if (!detail::is_zero(m)) {
      const auto up = static_cast<unsigned>(FracBits - frac);  // 0..64
      overflow = m.hi != 0 || up >= 64 || m.lo > (limit >> up);
      if (!overflow) m.lo <<= up;
    }
    if (overflow) {
      if constexpr (O == Overflow::checked) detail::precondition_failed();
      return {negative ? min() : max(), true};
    }
    if constexpr (Signed) {
      return {Q(static_cast<storage_type>(detail::apply_sign(m.lo, negative))), false};
    } else {
      return {Q(static_cast<storage_type>(m.lo)), false};  // negative here means m == 0
    }
  }

  friend constexpr bool operator==(Q, Q) = default;
  friend constexpr auto operator<=>(Q, Q) = default;

 private:
  static constexpr std::uint64_t kPositiveLimit = static_cast<std::uint64_t>(max_raw);
  static constexpr std::uint64_t kNegativeLimit =
      Signed ? detail::magnitude(static_cast<std::int64_t>(min_raw)) : 0;

  constexpr explicit Q(storage_type raw) : raw_(raw) {}

  storage_type raw_ = 0;
};

// a + b, clamped to the format's range.
template <int I, int F, bool S>
constexpr Q<I, F, S> add_sat(Q<I, F, S> a, Q<I, F, S> b) {
  using T = Q<I, F, S>;
  if constexpr (S) {
    const std::int64_t x = a.raw(), y = b.raw();
    if (y > 0 && x > std::int64_t{T::max_raw} - y) return T::max();
    if (y < 0 && x < std::int64_t{T::min_raw} - y) return T::min();
    return T::from_raw(x + y);
  } else {
    const std::uint64_t x = a.raw(), y = b.raw();
    if (x > std::uint64_t{T::max_raw} - y) return T::max();
    return T::from_raw(x + y);
  }
}

// a - b, clamped to the format's range (an unsigned difference below zero gives 0).
template <int I, int F, bool S>
constexpr Q<I, F, S> sub_sat(Q<I, F, S> a, Q<I, F, S> b) {
  using T = Q<I, F, S>;
  if constexpr (S) {
    const std::int64_t x = a.raw(), y = b.raw();
    if (y < 0 && x > std::int64_t{T::max_raw} + y) return T::max();
    if (y > 0 && x < std::int64_t{T::min_raw} + y) return T::min();
    return T::from_raw(x - y);
  } else {
    const std::uint64_t x = a.raw(), y = b.raw();
    if (x < y) return T::min();
    return T::from_raw(x - y);
  }
}

// The exact product in a format wide enough for every product of the two formats:
//   Q<a, b> x Q<c, d>                    -> Q<a + c + 1, b + d>  signed; the extra integer bit
//                                                                 holds -2^a * -2^c = 2^(a+c)
//   Q<a, b> x Q<c, d, false> (either way) -> Q<a + c, b + d>       signed
//   Q<a, b, false> x Q<c, d, false>      -> Q<a + c, b + d, false>
// The product must fit 64 bits; for wider products use mul<ResultQ>.
template <int I1, int F1, bool S1, int I2, int F2, bool S2>
constexpr auto mul_wide(Q<I1, F1, S1> x, Q<I2, F2, S2> y) {
  constexpr bool kSigned = S1 || S2;
  constexpr int kIntBits = I1 + I2 + ((S1 && S2) ? 1 : 0);
  static_assert(kIntBits + F1 + F2 + (kSigned ? 1 : 0) <= 64,
                "mul_wide: the exact product needs more than 64 bits; use mul<ResultQ>");
  using P = Q<kIntBits, F1 + F2, kSigned>;
  // Multiply modulo 2^64: the exact product fits P, so the wrapped result is the exact one.
  if constexpr (kSigned) {
    const auto a = static_cast<std::uint64_t>(static_cast<std::int64_t>(x.raw()));
    const auto b = static_cast<std::uint64_t>(static_cast<std::int64_t>(y.raw()));
    return P::from_raw(static_cast<std::int64_t>(a * b));
  } else {
    return P::from_raw(std::uint64_t{x.raw()} * std::uint64_t{y.raw()});
  }
}

// x * y rounded to ResultQ's step and clamped to its range; any two formats (the product is
// formed exactly in 128 bits). mul_wide(x, y).convert<ResultQ, R>() gives the same value plus the
// saturation flag, where the product fits 64 bits.
template <class ResultQ, Rounding R = kDefaultRounding, int I1, int F1, bool S1, int I2, int F2,
          bool S2>
  requires QFormat<ResultQ>
constexpr ResultQ mul(Q<I1, F1, S1> x, Q<I2, F2, S2> y) {
  const detail::SignMagnitude a = detail::sign_magnitude(x.raw());
  const detail::SignMagnitude b = detail::sign_magnitude(y.raw());
  return ResultQ::template from_scaled<R>(a.negative != b.negative,
                                          detail::mul_64x64(a.magnitude, b.magnitude), F1 + F2)
      .value;
}

}  // namespace bolo::fx
