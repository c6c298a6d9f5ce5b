#pragma once
// Shared helpers for the fixed_point tests: long double references, random raw values, and a
// failure collector that keeps millions of comparisons out of Catch's assertion machinery.

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

#include "bolo/fixed_point/q.hpp"
#include "bolo/fixed_point/rounding.hpp"

namespace bolo::fx::test {

using ld = long double;

// Significand bits of long double: 64 on x86-64 (x87), 113 on aarch64 (binary128), 53 on armhf
// (binary64). References are only used where they are exact for that width (see kRefBits).
inline constexpr int kLongDoubleDigits = std::numeric_limits<long double>::digits;
// Random operands carry at most this many significant bits, so they and their scaled values are
// exact long doubles on every target (all 64 bits on x86-64 and aarch64).
inline constexpr int kRefBits = kLongDoubleDigits < 64 ? kLongDoubleDigits : 64;
// ... and products of two such operands need at most kProductBits each.
inline constexpr int kProductBits = kLongDoubleDigits / 2 < 32 ? kLongDoubleDigits / 2 : 32;

inline constexpr std::uint64_t kSeed = 0x5EED'B010'F1ED'0001ull;

inline constexpr std::array<Rounding, 4> kRoundings{Rounding::nearest_away, Rounding::nearest_even,
                                                    Rounding::floor, Rounding::toward_zero};

inline const char* name(Rounding r) {
  switch (r) {
    case Rounding::nearest_away:
      return "nearest_away";
    case Rounding::nearest_even:
      return "nearest_even";
    case Rounding::floor:
      return "floor";
    case Rounding::toward_zero:
      return "toward_zero";
  }
  return "?";
}

// Calls f(std::integral_constant<Rounding, R>{}) for every rounding mode, so a loop body can
// pass the mode as a template argument.
template <class F>
void for_each_rounding(F&& f) {
  f(std::integral_constant<Rounding, Rounding::nearest_away>{});
  f(std::integral_constant<Rounding, Rounding::nearest_even>{});
  f(std::integral_constant<Rounding, Rounding::floor>{});
  f(std::integral_constant<Rounding, Rounding::toward_zero>{});
}

// The reference rounding of an exact long double to an integer, by the C library.
inline ld round_ref(ld x, Rounding r) {
  switch (r) {
    case Rounding::nearest_away:
      return std::round(x);  // ties away from zero
    case Rounding::nearest_even:
      return std::nearbyint(x);  // FE_TONEAREST: ties to even
    case Rounding::floor:
      return std::floor(x);
    case Rounding::toward_zero:
      return std::trunc(x);
  }
  return x;
}

// Catch2 is far too slow for one assertion per exhaustive case: collect, then assert once.
class Failures {
 public:
  template <class Describe>
  void check(bool ok, Describe&& describe) {
    ++checked_;
    if (ok) return;
    if (failed_++ < 8) log_ += describe() + "\n";
  }
  std::uint64_t failed() const { return failed_; }
  std::uint64_t checked() const { return checked_; }
  const std::string& log() const { return log_; }

 private:
  std::uint64_t checked_ = 0;
  std::uint64_t failed_ = 0;
  std::string log_;
};

#define BOLO_FX_REQUIRE_NO_FAILURES(failures)             \
  do {                                                    \
    INFO((failures).log());                               \
    INFO("checked " << (failures).checked() << " cases"); \
    CHECK((failures).failed() == 0);                      \
  } while (false)

template <class... Args>
std::string describe(const Args&... args) {
  std::ostringstream out;
  out.precision(21);
  (out << ... << args);
  return out.str();
}

// Raw value as a long double (exact for up to kLongDoubleDigits significant bits).
template <class T>
ld as_ld(T v) {
  return static_cast<ld>(v);
}

// The expected raw result of rounding `exact` (in raw units of To) to an integer and clamping it
// to To's range, compared with a result; exact comparisons on every target.
template <class To>
struct Expected {
  ld value = 0;  // the rounded value (meaningful when !saturated)
  bool saturated = false;
  bool high = false;  // which rail when saturated
};

template <class To>
Expected<To> expected_raw(ld exact, Rounding r) {
  const ld rounded = round_ref(exact, r);
  const ld upper = std::ldexp(ld{1}, To::value_bits);  // max_raw + 1, a power of two
  const ld lower = To::is_signed ? -upper : ld{0};     // min_raw
  if (rounded >= upper) return {0, true, true};
  if (rounded < lower) return {0, true, false};
  return {rounded, false, false};
}

template <class To>
bool matches(const Expected<To>& e, const Converted<To>& got) {
  if (e.saturated) return got.saturated && got.value == (e.high ? To::max() : To::min());
  return !got.saturated && as_ld(got.value.raw()) == e.value;
}

template <class To>
bool matches(const Expected<To>& e, const To& got) {
  if (e.saturated) return got == (e.high ? To::max() : To::min());
  return as_ld(got.raw()) == e.value;
}

// A random raw value of format QT: a uniformly chosen bit length (so small and large magnitudes
// are equally likely), at most `significant` significant bits, a random sign; one draw in eight
// is an edge (min, max, 0, +-1, min + 1, max - 1).
// Keeps the `significant` most significant bits of a magnitude (clears the ones below).
inline std::uint64_t keep_top_bits(std::uint64_t magnitude, int significant) {
  int length = 0;
  while (length < 64 && (magnitude >> length) != 0) ++length;
  if (length <= significant) return magnitude;
  return magnitude & ~((std::uint64_t{1} << (length - significant)) - 1);
}

template <class QT>
typename QT::storage_type random_raw(std::mt19937_64& rng, int significant = kRefBits) {
  using S = typename QT::storage_type;
  bool negative = false;
  std::uint64_t magnitude = 0;
  if (rng() % 8 == 0) {
    // An edge, with its magnitude cut to `significant` bits (min_raw + 1 = -(2^n - 1) becomes
    // the most negative value with that many bits).
    const S edges[] = {QT::min_raw,
                       QT::max_raw,
                       S{0},
                       S{1},
                       QT::is_signed ? static_cast<S>(-1) : S{1},
                       static_cast<S>(QT::min_raw + 1),
                       static_cast<S>(QT::max_raw - 1)};
    const S edge = edges[rng() % 7];
    const auto sm = detail::sign_magnitude(edge);
    negative = sm.negative;
    magnitude = keep_top_bits(sm.magnitude, significant);
  } else {
    const int length = static_cast<int>(rng() % static_cast<std::uint64_t>(QT::value_bits + 1));
    if (length > 0) {
      const int sig = std::min(length, significant);
      const std::uint64_t top = (rng() >> (64 - sig)) | (std::uint64_t{1} << (sig - 1));
      magnitude = top << (length - sig);
    }
    negative = QT::is_signed && (rng() & 1u) != 0;
  }
  if constexpr (QT::is_signed) {
    // magnitude <= 2^value_bits <= 2^63; negate in unsigned arithmetic (INT64_MIN is exact).
    return static_cast<S>(detail::apply_sign(magnitude, negative));
  } else {
    return static_cast<S>(magnitude);
  }
}

}  // namespace bolo::fx::test
