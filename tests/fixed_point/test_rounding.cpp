// shift_right, divide and saturate against long double references: exhaustive over 16-bit
// inputs for every rounding mode, the same inputs scaled to the top of the 64-bit range, random
// 64-bit values, and the explicit ties.

#include <cstdint>
#include <limits>
#include <random>

#include "bolo/fixed_point/rounding.hpp"
#include "fx_test_support.hpp"

namespace bolo::fx::test {
namespace {

constexpr std::int64_t kI64Min = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t kI64Max = std::numeric_limits<std::int64_t>::max();
constexpr std::uint64_t kU64Max = std::numeric_limits<std::uint64_t>::max();

// --- constexpr-ness and the documented examples -------------------------------------------------
static_assert(shift_right(std::int64_t{5}, 1) == 3);  // 2.5 -> 3 (default: ties away)
static_assert(shift_right(std::int64_t{-5}, 1) == -3);
static_assert(shift_right<Rounding::nearest_even>(std::int64_t{5}, 1) == 2);
static_assert(shift_right<Rounding::nearest_even>(std::int64_t{7}, 1) == 4);
static_assert(shift_right<Rounding::nearest_even>(std::int64_t{-5}, 1) == -2);
static_assert(shift_right<Rounding::floor>(std::int64_t{-5}, 1) == -3);
static_assert(shift_right<Rounding::toward_zero>(std::int64_t{-5}, 1) == -2);
static_assert(shift_right(kI64Min, 0) == kI64Min);
static_assert(shift_right(kI64Min, 62) == -2);
static_assert(shift_right(kI64Min, 63) == -1);
static_assert(shift_right(kI64Min, 64) == -1);  // -1/2: tie, away from zero
static_assert(shift_right<Rounding::nearest_even>(kI64Min, 64) == 0);
static_assert(shift_right(kI64Max, 62) == 2);
static_assert(shift_right(std::uint64_t{3}, 1) == 2);
static_assert(shift_right(kU64Max, 63) == 2);
static_assert(shift_right(kU64Max, 64) == 1);
static_assert(shift_right<Rounding::floor>(kU64Max, 64) == 0);
static_assert(shift_right(kU64Max, 200) == 0);
static_assert(divide(std::uint64_t{5}, std::uint64_t{2}) == 3);
static_assert(divide<Rounding::nearest_even>(std::uint64_t{5}, std::uint64_t{2}) == 2);
static_assert(divide(kU64Max, kU64Max) == 1);
static_assert(divide(kU64Max, std::uint64_t{2}) == std::uint64_t{1} << 63);
static_assert(divide(std::int64_t{-7}, std::int64_t{2}) == -4);
static_assert(divide<Rounding::nearest_even>(std::int64_t{-7}, std::int64_t{2}) == -4);
static_assert(divide<Rounding::nearest_even>(std::int64_t{-5}, std::int64_t{2}) == -2);
static_assert(divide<Rounding::floor>(std::int64_t{7}, std::int64_t{-2}) == -4);
static_assert(divide<Rounding::toward_zero>(std::int64_t{7}, std::int64_t{-2}) == -3);
static_assert(divide(kI64Min, std::int64_t{-1}) == kI64Max);  // saturates
static_assert(divide(kI64Min, std::int64_t{1}) == kI64Min);
static_assert(saturate<std::int8_t>(300) == 127);
static_assert(saturate<std::int8_t>(-300) == -128);
static_assert(saturate<std::uint8_t>(-1) == 0);
static_assert(saturate<std::uint16_t>(70000) == 65535);
static_assert(saturate<std::int32_t>(kI64Min) == std::numeric_limits<std::int32_t>::min());
static_assert(saturate<std::uint32_t>(kI64Max) == std::numeric_limits<std::uint32_t>::max());
static_assert(saturate<std::uint64_t>(-5) == 0);
static_assert(saturate<std::uint64_t>(kI64Max) == static_cast<std::uint64_t>(kI64Max));
static_assert(saturate<std::int64_t>(kI64Min) == kI64Min);

// The reference for v / 2^s.
template <class T>
bool shift_ok(T v, unsigned s, Rounding r, T got) {
  return as_ld(got) == round_ref(std::ldexp(as_ld(v), -static_cast<int>(s)), r);
}

template <Rounding R>
void check_shifts_16_bit(Failures& f) {
  for (std::int32_t i = -32768; i <= 32767; ++i) {
    for (unsigned s = 0; s <= 20; ++s) {
      const std::int64_t v = i;
      const std::int64_t got = shift_right<R>(v, s);
      f.check(shift_ok(v, s, R, got),
              [&] { return describe(name(R), " ", v, " >> ", s, " = ", got); });
      // The same 16 significant bits at the top of the range (down to INT64_MIN).
      const std::int64_t high = v * (std::int64_t{1} << 48);
      const unsigned sh = s + 44;  // 44..64
      const std::int64_t got_high = shift_right<R>(high, sh);
      f.check(shift_ok(high, sh, R, got_high),
              [&] { return describe(name(R), " ", high, " >> ", sh, " = ", got_high); });
    }
  }
  for (std::uint32_t i = 0; i <= 65535; ++i) {
    for (unsigned s = 0; s <= 20; ++s) {
      const std::uint64_t v = i;
      const std::uint64_t got = shift_right<R>(v, s);
      f.check(shift_ok(v, s, R, got),
              [&] { return describe(name(R), " ", v, " >> ", s, " = ", got); });
      const std::uint64_t high = v << 48;
      const unsigned sh = s + 45;  // 45..65
      const std::uint64_t got_high = shift_right<R>(high, sh);
      f.check(shift_ok(high, sh, R, got_high),
              [&] { return describe(name(R), " ", high, " >> ", sh, " = ", got_high); });
    }
  }
}

TEST_CASE("shift_right: exhaustive over 16-bit values, every mode", "[fixed_point][rounding]") {
  REQUIRE(std::fegetround() == FE_TONEAREST);  // nearbyint is the ties-to-even reference
  Failures f;
  for_each_rounding([&](auto r) { check_shifts_16_bit<decltype(r)::value>(f); });
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("shift_right: random 64-bit values and every shift 0..70", "[fixed_point][rounding]") {
  std::mt19937_64 rng(kSeed);
  Failures f;
  for_each_rounding([&](auto rc) {
    constexpr Rounding R = decltype(rc)::value;
    for (int n = 0; n < 3000; ++n) {
      const auto v = static_cast<std::int64_t>(random_raw<Q<63, 0>>(rng));
      const auto u = static_cast<std::uint64_t>(random_raw<Q<64, 0, false>>(rng));
      for (unsigned s = 0; s <= 70; ++s) {
        const std::int64_t got = shift_right<R>(v, s);
        f.check(shift_ok(v, s, R, got),
                [&] { return describe(name(R), " ", v, " >> ", s, " = ", got); });
        const std::uint64_t got_u = shift_right<R>(u, s);
        f.check(shift_ok(u, s, R, got_u),
                [&] { return describe(name(R), " ", u, " >> ", s, " = ", got_u); });
      }
    }
  });
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("shift_right: ties", "[fixed_point][rounding]") {
  // +-(2k + 1) / 2 for k = 0..3 with every mode; and a tie at the top of the range.
  struct Case {
    std::int64_t v;
    std::int64_t away, even, floor, trunc;
  };
  const Case cases[] = {
      {1, 1, 0, 0, 0}, {-1, -1, 0, -1, 0},   {3, 2, 2, 1, 1}, {-3, -2, -2, -2, -1},
      {5, 3, 2, 2, 2}, {-5, -3, -2, -3, -2}, {7, 4, 4, 3, 3}, {-7, -4, -4, -4, -3},
  };
  for (const Case& c : cases) {
    INFO("v = " << c.v << " / 2");
    CHECK(shift_right<Rounding::nearest_away>(c.v, 1) == c.away);
    CHECK(shift_right<Rounding::nearest_even>(c.v, 1) == c.even);
    CHECK(shift_right<Rounding::floor>(c.v, 1) == c.floor);
    CHECK(shift_right<Rounding::toward_zero>(c.v, 1) == c.trunc);
    // The same ties with 40 more discarded bits.
    const std::int64_t scaled = c.v * (std::int64_t{1} << 40);
    CHECK(shift_right<Rounding::nearest_away>(scaled, 41) == c.away);
    CHECK(shift_right<Rounding::nearest_even>(scaled, 41) == c.even);
    CHECK(shift_right<Rounding::floor>(scaled, 41) == c.floor);
    CHECK(shift_right<Rounding::toward_zero>(scaled, 41) == c.trunc);
  }
  // (2^63 - 2^62) / 2^63 = 1/2 exactly.
  const std::uint64_t half_top = std::uint64_t{3} << 62;  // 1.5 * 2^63
  CHECK(shift_right<Rounding::nearest_away>(half_top, 63) == 2);
  CHECK(shift_right<Rounding::nearest_even>(half_top, 63) == 2);
  CHECK(shift_right<Rounding::nearest_even>(std::uint64_t{1} << 62, 63) == 0);
  CHECK(shift_right<Rounding::nearest_away>(std::uint64_t{1} << 62, 63) == 1);
}

// --- divide --------------------------------------------------------------------------------------

// num / den by long double: exact classification as long as |num|, |den| <= 2^B with
// 2B + 1 < digits (the quotient's rounding error is then below half the distance from any
// non-tie to a tie or an integer).
constexpr int kDivideBits = (kLongDoubleDigits - 2) / 2;

template <class T>
bool divide_ok(T num, T den, Rounding r, T got) {
  return as_ld(got) == round_ref(as_ld(num) / as_ld(den), r);
}

TEST_CASE("divide: exhaustive small operands, every mode", "[fixed_point][rounding]") {
  Failures f;
  for_each_rounding([&](auto rc) {
    constexpr Rounding R = decltype(rc)::value;
    for (std::int64_t num = -300; num <= 300; ++num) {
      for (std::int64_t den = -40; den <= 40; ++den) {
        if (den == 0) continue;
        const std::int64_t got = divide<R>(num, den);
        f.check(divide_ok(num, den, R, got),
                [&] { return describe(name(R), " ", num, " / ", den, " = ", got); });
        if (num >= 0 && den > 0) {
          const auto un = static_cast<std::uint64_t>(num), ud = static_cast<std::uint64_t>(den);
          const std::uint64_t got_u = divide<R>(un, ud);
          f.check(divide_ok(un, ud, R, got_u),
                  [&] { return describe(name(R), " ", un, " / ", ud, " = ", got_u); });
        }
      }
    }
  });
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("divide: random operands up to the exact-reference width", "[fixed_point][rounding]") {
  std::mt19937_64 rng(kSeed + 1);
  using Operand = Q<kDivideBits, 0>;
  using UOperand = Q<kDivideBits, 0, false>;
  Failures f;
  for_each_rounding([&](auto rc) {
    constexpr Rounding R = decltype(rc)::value;
    for (int n = 0; n < 200000; ++n) {
      const std::int64_t num = random_raw<Operand>(rng);
      std::int64_t den = random_raw<Operand>(rng);
      if (den == 0) den = 1;
      const std::int64_t got = divide<R>(num, den);
      f.check(divide_ok(num, den, R, got),
              [&] { return describe(name(R), " ", num, " / ", den, " = ", got); });
      const std::uint64_t un = random_raw<UOperand>(rng);
      std::uint64_t ud = random_raw<UOperand>(rng);
      if (ud == 0) ud = 3;
      const std::uint64_t got_u = divide<R>(un, ud);
      f.check(divide_ok(un, ud, R, got_u),
              [&] { return describe(name(R), " ", un, " / ", ud, " = ", got_u); });
      // A constructed tie: (2q + 1) * d / (2d) = q + 1/2.
      const std::int64_t q = num % 4096, d = den % 4096 == 0 ? 1 : den % 4096;
      const std::int64_t tie_num = (2 * q + 1) * d, tie_den = 2 * d;
      const std::int64_t got_tie = divide<R>(tie_num, tie_den);
      f.check(divide_ok(tie_num, tie_den, R, got_tie),
              [&] { return describe(name(R), " ", tie_num, " / ", tie_den, " = ", got_tie); });
    }
  });
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("divide: full 64-bit range properties", "[fixed_point][rounding]") {
  // With |num|, |den| up to 2^64 the long double quotient is not exact, so check the defining
  // property with exact integer arithmetic instead: for den > 0 and num >= 0, the truncated
  // quotient t = num / den and remainder r = num % den give
  //   floor, toward_zero: t;   nearest: t + 1 iff r > den - r, or r == den - r (a tie) and
  //   (away, or t is odd).
  std::mt19937_64 rng(kSeed + 2);
  Failures f;
  for (int n = 0; n < 200000; ++n) {
    const std::uint64_t num = random_raw<Q<64, 0, false>>(rng);
    std::uint64_t den = random_raw<Q<64, 0, false>>(rng);
    if (den == 0) den = 7;
    const std::uint64_t t = num / den, r = num % den, rest = den - r;
    const bool above = r > rest, tie = r != 0 && r == rest;
    const std::uint64_t away = t + ((above || tie) ? 1 : 0);
    const std::uint64_t even = t + ((above || (tie && (t & 1) != 0)) ? 1 : 0);
    f.check(divide<Rounding::nearest_away>(num, den) == away &&
                divide<Rounding::nearest_even>(num, den) == even &&
                divide<Rounding::floor>(num, den) == t &&
                divide<Rounding::toward_zero>(num, den) == t,
            [&] { return describe(num, " / ", den); });
    // Signed: the magnitude rounds like the unsigned quotient; the sign goes back on; floor rounds
    // an inexact negative quotient away from zero.
    const auto sn = static_cast<std::int64_t>(random_raw<Q<63, 0>>(rng));
    auto sd = static_cast<std::int64_t>(random_raw<Q<63, 0>>(rng));
    if (sd == 0) sd = -3;
    if (sn == kI64Min && sd == -1) continue;
    const bool negative = (sn < 0) != (sd < 0);
    const std::uint64_t mn =
        sn < 0 ? 0 - static_cast<std::uint64_t>(sn) : static_cast<std::uint64_t>(sn);
    const std::uint64_t md =
        sd < 0 ? 0 - static_cast<std::uint64_t>(sd) : static_cast<std::uint64_t>(sd);
    const std::uint64_t mt = mn / md, mr = mn % md;
    auto with_sign = [&](std::uint64_t m) {
      return negative ? static_cast<std::int64_t>(0 - m) : static_cast<std::int64_t>(m);
    };
    f.check(divide<Rounding::nearest_away>(sn, sd) ==
                    with_sign(divide<Rounding::nearest_away>(mn, md)) &&
                divide<Rounding::nearest_even>(sn, sd) ==
                    with_sign(divide<Rounding::nearest_even>(mn, md)) &&
                divide<Rounding::toward_zero>(sn, sd) == with_sign(mt) &&
                divide<Rounding::floor>(sn, sd) == with_sign(mt + ((negative && mr != 0) ? 1 : 0)),
            [&] { return describe(sn, " / ", sd); });
  }
  BOLO_FX_REQUIRE_NO_FAILURES(f);
  CHECK(divide(kI64Min, std::int64_t{-1}) == kI64Max);
  CHECK(divide<Rounding::floor>(kI64Min, std::int64_t{-1}) == kI64Max);
  CHECK(divide(kI64Min, kI64Min) == 1);
  CHECK(divide(kI64Max, kI64Min) == -1);
  CHECK(divide<Rounding::toward_zero>(kI64Max, kI64Min) == 0);
  CHECK(divide(kI64Min, std::int64_t{2}) == kI64Min / 2);
  CHECK(divide(kU64Max, std::uint64_t{1}) == kU64Max);
  CHECK(divide<Rounding::nearest_even>(kU64Max, std::uint64_t{2}) == std::uint64_t{1} << 63);
  CHECK(divide<Rounding::floor>(kU64Max, std::uint64_t{2}) == kU64Max / 2);
}

TEST_CASE("divide: a zero divisor is defined at run time", "[fixed_point][rounding]") {
  volatile std::uint64_t zero = 0;  // keep it out of constant evaluation
  CHECK(divide(std::uint64_t{5}, zero) == kU64Max);
  CHECK(divide(std::uint64_t{0}, zero) == 0);
  CHECK(divide(std::int64_t{-5}, static_cast<std::int64_t>(zero)) == kI64Min);
  CHECK(divide(std::int64_t{5}, static_cast<std::int64_t>(zero)) == kI64Max);
  CHECK(divide(std::int64_t{0}, static_cast<std::int64_t>(zero)) == 0);
}

// --- saturate ------------------------------------------------------------------------------------

template <class T>
bool saturate_ok(std::int64_t v) {
  const ld lo = as_ld(std::numeric_limits<T>::min()), hi = as_ld(std::numeric_limits<T>::max());
  return as_ld(saturate<T>(v)) == std::clamp(as_ld(v), lo, hi);
}

TEST_CASE("saturate: exhaustive over 16-bit values, and the 64-bit edges",
          "[fixed_point][rounding]") {
  Failures f;
  for (std::int64_t v = -65536; v <= 65536; ++v) {
    f.check(saturate_ok<std::int8_t>(v) && saturate_ok<std::uint8_t>(v) &&
                saturate_ok<std::int16_t>(v) && saturate_ok<std::uint16_t>(v) &&
                saturate_ok<std::int32_t>(v) && saturate_ok<std::uint32_t>(v),
            [&] { return describe("saturate ", v); });
  }
  std::mt19937_64 rng(kSeed + 3);
  for (int n = 0; n < 100000; ++n) {
    const std::int64_t v = random_raw<Q<63, 0>>(rng);
    f.check(saturate_ok<std::int8_t>(v) && saturate_ok<std::uint8_t>(v) &&
                saturate_ok<std::int16_t>(v) && saturate_ok<std::uint16_t>(v) &&
                saturate_ok<std::int32_t>(v) && saturate_ok<std::uint32_t>(v) &&
                saturate<std::int64_t>(v) == v &&
                saturate<std::uint64_t>(v) == (v < 0 ? 0 : static_cast<std::uint64_t>(v)),
            [&] { return describe("saturate ", v); });
  }
  BOLO_FX_REQUIRE_NO_FAILURES(f);
  CHECK(saturate<std::int32_t>(std::int64_t{1} << 31) == std::numeric_limits<std::int32_t>::max());
  CHECK(saturate<std::int32_t>(-(std::int64_t{1} << 31)) ==
        std::numeric_limits<std::int32_t>::min());
  CHECK(saturate<std::int32_t>(-(std::int64_t{1} << 31) - 1) ==
        std::numeric_limits<std::int32_t>::min());
  CHECK(saturate<std::uint32_t>(std::int64_t{1} << 32) ==
        std::numeric_limits<std::uint32_t>::max());
  CHECK(saturate<std::uint32_t>((std::int64_t{1} << 32) - 1) ==
        std::numeric_limits<std::uint32_t>::max());
  CHECK(saturate<std::uint64_t>(kI64Min) == 0);
  CHECK(saturate<std::int8_t>(kI64Max) == 127);
}

}  // namespace
}  // namespace bolo::fx::test
