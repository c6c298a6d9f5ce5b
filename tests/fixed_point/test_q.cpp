// Q<IntBits, FracBits, Signed> against long double references: exhaustive over 8-bit formats,
// random (fixed seed) over wider ones, every rounding mode, explicit ties and both rails.

#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <random>

#include "bolo/fixed_point/q.hpp"
#include "fx_test_support.hpp"

namespace bolo::fx::test {
namespace {

// --- formats, storage and constants (all at compile time) --------------------------------------
static_assert(std::same_as<Q<3, 4>::storage_type, std::int8_t>);
static_assert(std::same_as<Q<2, 4>::storage_type, std::int8_t>);  // 7 bits in an int8
static_assert(std::same_as<Q<8, 0, false>::storage_type, std::uint8_t>);
static_assert(std::same_as<Q<1, 14>::storage_type, std::int16_t>);
static_assert(std::same_as<Q<0, 16, false>::storage_type, std::uint16_t>);
static_assert(std::same_as<Q<8, 8>::storage_type, std::int32_t>);  // 17 bits
static_assert(std::same_as<Q<8, 24, false>::storage_type, std::uint32_t>);
static_assert(std::same_as<Q<8, 24>::storage_type, std::int64_t>);  // 33 bits
static_assert(std::same_as<Q<0, 64, false>::storage_type, std::uint64_t>);
static_assert(std::same_as<Q<0, 63>::storage_type, std::int64_t>);
static_assert(sizeof(Q<1, 14>) == 2 && sizeof(Q<8, 24, false>) == 4);

static_assert(Q<3, 4>::min_raw == -128 && Q<3, 4>::max_raw == 127);
static_assert(Q<2, 4>::min_raw == -64 && Q<2, 4>::max_raw == 63);
static_assert(Q<4, 4, false>::min_raw == 0 && Q<4, 4, false>::max_raw == 255);
static_assert(Q<0, 64, false>::max_raw == std::numeric_limits<std::uint64_t>::max());
static_assert(Q<0, 63>::min_raw == std::numeric_limits<std::int64_t>::min());
static_assert(Q<1, 14>::min().to_double() == -2.0);
static_assert(Q<1, 14>::max().to_double() == 2.0 - 1.0 / 16384);
static_assert(Q<1, 14>::epsilon().to_double() == 1.0 / 16384);
static_assert(Q<8, 24, false>::max().raw() == 0xFFFF'FFFFu);
static_assert(Q<1, 14>{}.raw() == 0);
static_assert(Q<2, 4>::from_raw(100) == Q<2, 4>::max());  // clamped to the format, not the int8
static_assert(Q<2, 4>::from_raw(-100) == Q<2, 4>::min());
static_assert(Q<4, 4, false>::from_raw(-1) == Q<4, 4, false>::min());
static_assert(Q<1, 14>::from_raw(1) < Q<1, 14>::from_raw(2));

// from_double / from_int / convert / mul are usable in constant expressions, and
// Overflow::checked accepts in-range constants (an out-of-range one does not compile: see
// compile_checked_overflow.cpp).
constexpr auto kHalf = Q<1, 14>::from_double<Rounding::nearest_away, Overflow::checked>(0.5);
static_assert(kHalf.value.raw() == 8192 && !kHalf.saturated);
static_assert(Q<1, 14>::from_double(3.0).saturated);
static_assert(Q<1, 14>::from_double(3.0).value == Q<1, 14>::max());
static_assert(Q<7, 0>::from_double(2.5).value.raw() == 3);
static_assert(Q<7, 0>::from_double<Rounding::nearest_even>(2.5).value.raw() == 2);
static_assert(Q<7, 0>::from_double(-2.5).value.raw() == -3);
static_assert(Q<8, 8>::from_int(3).value.raw() == 768);
static_assert(Q<8, 8>::from_int<Overflow::checked>(-256).value.raw() == -65536);
static_assert(Q<8, 8>::from_int(256).saturated);
static_assert(Q<3, 4>::from_raw(40).convert<Q<7, 0>>().value.raw() == 3);  // 2.5
static_assert(Q<3, 4>::from_raw(40).convert<Q<7, 0>, Rounding::nearest_even>().value.raw() == 2);
static_assert(mul_wide(Q<3, 4>::min(), Q<3, 4>::min()).raw() == 16384);  // (-8)(-8) = 64
static_assert(std::same_as<decltype(mul_wide(Q<3, 4>{}, Q<3, 4>{})), Q<7, 8>>);
static_assert(std::same_as<decltype(mul_wide(Q<3, 4>{}, Q<4, 4, false>{})), Q<7, 8>>);
static_assert(std::same_as<decltype(mul_wide(Q<4, 4, false>{}, Q<3, 4>{})), Q<7, 8>>);
static_assert(std::same_as<decltype(mul_wide(Q<4, 4, false>{}, Q<4, 4, false>{})), Q<8, 8, false>>);
static_assert(std::same_as<decltype(mul_wide(Q<15, 16>{}, Q<15, 16>{})), Q<31, 32>>);
static_assert(mul<Q<3, 4>>(Q<3, 4>::min(), Q<3, 4>::min()) == Q<3, 4>::max());
static_assert(add_sat(Q<3, 4>::max(), Q<3, 4>::epsilon()) == Q<3, 4>::max());
static_assert(sub_sat(Q<3, 4>::min(), Q<3, 4>::epsilon()) == Q<3, 4>::min());

// --- from_raw / to_double --------------------------------------------------------------------
TEST_CASE("Q: from_raw keeps in-range values and clamps to the format's range",
          "[fixed_point][q]") {
  Failures f;
  for (std::int32_t v = -300; v <= 300; ++v) {
    const auto narrow = Q<2, 4>::from_raw(v);  // 7-bit format in an int8
    const auto full = Q<3, 4>::from_raw(v);
    const auto unsigned7 = Q<3, 4, false>::from_raw(v);
    f.check(narrow.raw() == std::clamp(v, -64, 63) && full.raw() == std::clamp(v, -128, 127) &&
                unsigned7.raw() == std::clamp(v, 0, 127),
            [&] { return describe("from_raw ", v); });
    f.check(narrow.to_double() == std::clamp(v, -64, 63) / 16.0,
            [&] { return describe("to_double ", v); });
  }
  BOLO_FX_REQUIRE_NO_FAILURES(f);
  CHECK(Q<63, 0>::from_raw(std::numeric_limits<std::uint64_t>::max()) == Q<63, 0>::max());
  CHECK(Q<0, 64, false>::from_raw(std::numeric_limits<std::int64_t>::min()) ==
        Q<0, 64, false>::min());
  CHECK(Q<0, 64, false>::from_raw(std::numeric_limits<std::uint64_t>::max()).raw() ==
        std::numeric_limits<std::uint64_t>::max());
}

// --- from_double ---------------------------------------------------------------------------------

template <class QT, Rounding R>
void check_from_double(double v, Failures& f) {
  const Converted<QT> got = QT::template from_double<R>(v);
  const Expected<QT> e = expected_raw<QT>(std::ldexp(static_cast<ld>(v), QT::frac_bits), R);
  f.check(matches(e, got), [&] {
    return describe(name(R), " from_double(", v, ") into Q<", QT::int_bits, ",", QT::frac_bits, ",",
                    QT::is_signed, "> = ", +got.value.raw(), got.saturated ? " (saturated)" : "");
  });
}

template <class QT>
void check_from_double_random(std::mt19937_64& rng, Failures& f) {
  for (int n = 0; n < 20000; ++n) {
    // A random double around the format's range and step: a 53-bit significand and an exponent
    // from 2^-(FracBits + 8) to 2^(IntBits + 4); one draw in four is an exact tie (k + 1/2) steps.
    double v;
    if (n % 4 == 0) {
      const auto k = static_cast<double>(rng() >> (64 - std::min(50, QT::value_bits + 1)));
      v = std::ldexp(k + 0.5, -QT::frac_bits);
    } else {
      const auto mantissa = static_cast<double>(rng() >> 11);  // 53 bits, exact
      const int span = QT::int_bits + QT::frac_bits + 12;
      const int exponent =
          static_cast<int>(rng() % static_cast<std::uint64_t>(span)) - QT::frac_bits - 8 - 53;
      v = std::ldexp(mantissa, exponent);
    }
    if ((rng() & 1u) != 0) v = -v;
    for_each_rounding([&](auto r) { check_from_double<QT, decltype(r)::value>(v, f); });
  }
}

TEST_CASE("Q: from_double against long double, every mode", "[fixed_point][q]") {
  std::mt19937_64 rng(kSeed + 10);
  Failures f;
  check_from_double_random<Q<3, 4>>(rng, f);
  check_from_double_random<Q<2, 4>>(rng, f);
  check_from_double_random<Q<4, 4, false>>(rng, f);
  check_from_double_random<Q<1, 14>>(rng, f);
  check_from_double_random<Q<8, 24, false>>(rng, f);
  check_from_double_random<Q<15, 16>>(rng, f);
  check_from_double_random<Q<0, 63>>(rng, f);
  check_from_double_random<Q<63, 0>>(rng, f);
  check_from_double_random<Q<0, 64, false>>(rng, f);
  check_from_double_random<Q<32, 32, false>>(rng, f);
  const double specials[] = {0.0,    -0.0,   1e-300,  -1e-300, 4.9e-324, -4.9e-324,           1e300,
                             -1e300, 0x1p63, -0x1p63, 0x1p64,  -0x1p64,  0x1.fffffffffffffp63};
  for (double v : specials) {
    for_each_rounding([&](auto r) {
      constexpr Rounding R = decltype(r)::value;
      check_from_double<Q<3, 4>, R>(v, f);
      check_from_double<Q<63, 0>, R>(v, f);
      check_from_double<Q<64, 0, false>, R>(v, f);
      check_from_double<Q<0, 64, false>, R>(v, f);
    });
  }
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("Q: from_double ties, rails and non-finite values", "[fixed_point][q]") {
  using I8 = Q<7, 0>;
  using U8 = Q<8, 0, false>;
  struct Tie {
    double v;
    int away, even, floor, trunc;
  };
  const Tie ties[] = {{0.5, 1, 0, 0, 0},      {-0.5, -1, 0, -1, 0}, {1.5, 2, 2, 1, 1},
                      {-1.5, -2, -2, -2, -1}, {2.5, 3, 2, 2, 2},    {-2.5, -3, -2, -3, -2}};
  for (const Tie& t : ties) {
    INFO("v = " << t.v);
    CHECK(I8::from_double<Rounding::nearest_away>(t.v).value.raw() == t.away);
    CHECK(I8::from_double<Rounding::nearest_even>(t.v).value.raw() == t.even);
    CHECK(I8::from_double<Rounding::floor>(t.v).value.raw() == t.floor);
    CHECK(I8::from_double<Rounding::toward_zero>(t.v).value.raw() == t.trunc);
  }
  // Rails: 127.5 rounds to 128 (saturated) with ties away, to 128 with ties even (128 is even).
  CHECK(I8::from_double(127.4).value.raw() == 127);
  CHECK(!I8::from_double(127.4).saturated);
  CHECK(I8::from_double(127.5).saturated);
  CHECK(I8::from_double<Rounding::floor>(127.5).value.raw() == 127);
  CHECK(!I8::from_double<Rounding::floor>(127.5).saturated);
  CHECK(I8::from_double(-128.5).saturated);
  CHECK(I8::from_double(-128.5).value == I8::min());
  CHECK(!I8::from_double<Rounding::nearest_even>(-128.5).saturated);  // -128 is even
  // Negative values into unsigned formats: -0.4 rounds to 0 (fine), -0.5 away from zero to -1.
  CHECK(!U8::from_double(-0.4).saturated);
  CHECK(U8::from_double(-0.4).value.raw() == 0);
  CHECK(U8::from_double(-0.5).saturated);
  CHECK(!U8::from_double<Rounding::nearest_even>(-0.5).saturated);
  CHECK(U8::from_double<Rounding::floor>(-0.1).saturated);
  CHECK(!U8::from_double<Rounding::toward_zero>(-0.9).saturated);
  // Non-finite.
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(I8::from_double(inf).value == I8::max());
  CHECK(I8::from_double(inf).saturated);
  CHECK(I8::from_double(-inf).value == I8::min());
  CHECK(I8::from_double(nan).value.raw() == 0);
  CHECK(I8::from_double(nan).saturated);
  // Overflow::checked at run time behaves like saturate.
  volatile double big = 1000.0;
  const auto checked = I8::from_double<kDefaultRounding, Overflow::checked>(big);
  CHECK(checked.saturated);
  CHECK(checked.value == I8::max());
}

// --- from_int ------------------------------------------------------------------------------------

template <class QT, class V>
void check_from_int(V v, Failures& f) {
  const Converted<QT> got = QT::from_int(v);
  const Expected<QT> e = expected_raw<QT>(std::ldexp(as_ld(v), QT::frac_bits), Rounding::floor);
  f.check(matches(e, got), [&] {
    return describe("from_int(", v, ") into Q<", QT::int_bits, ",", QT::frac_bits, ",",
                    QT::is_signed, "> = ", +got.value.raw(), got.saturated ? " (saturated)" : "");
  });
}

TEST_CASE("Q: from_int, exhaustive small and random 64-bit", "[fixed_point][q]") {
  Failures f;
  for (std::int64_t v = -70000; v <= 70000; ++v) {
    check_from_int<Q<3, 4>>(v, f);
    check_from_int<Q<2, 4>>(v, f);
    check_from_int<Q<4, 4, false>>(v, f);
    check_from_int<Q<0, 7>>(v, f);
    check_from_int<Q<15, 16>>(v, f);
    check_from_int<Q<16, 0, false>>(v, f);
  }
  std::mt19937_64 rng(kSeed + 11);
  for (int n = 0; n < 50000; ++n) {
    const auto s = static_cast<std::int64_t>(random_raw<Q<63, 0>>(rng));
    const auto u = static_cast<std::uint64_t>(random_raw<Q<64, 0, false>>(rng));
    check_from_int<Q<31, 32>>(s, f);
    check_from_int<Q<63, 0>>(s, f);
    check_from_int<Q<64, 0, false>>(s, f);
    check_from_int<Q<32, 32, false>>(u, f);
    check_from_int<Q<63, 0>>(u, f);
    check_from_int<Q<64, 0, false>>(u, f);
    check_from_int<Q<0, 64, false>>(u, f);
  }
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

// --- convert between formats ---------------------------------------------------------------------

template <class... Ts>
struct List {};

// Every storage width, signed and unsigned, full-width and narrower than their storage, integer-
// only and fraction-only.
using Formats =
    List<Q<3, 4>, Q<2, 4>, Q<7, 0, false>, Q<5, 5, false>, Q<1, 14>, Q<8, 24, false>, Q<15, 16>,
         Q<10, 20>, Q<20, 30, false>, Q<0, 63>, Q<63, 0>, Q<32, 32, false>, Q<0, 64, false>>;

template <class From, class To>
void check_convert(std::mt19937_64& rng, Failures& f) {
  for (int n = 0; n < 400; ++n) {
    const From x = From::from_raw(random_raw<From>(rng));
    const ld exact = std::ldexp(as_ld(x.raw()), To::frac_bits - From::frac_bits);
    for_each_rounding([&](auto rc) {
      constexpr Rounding R = decltype(rc)::value;
      const Converted<To> got = x.template convert<To, R>();
      f.check(matches(expected_raw<To>(exact, R), got), [&] {
        return describe(name(R), " Q<", From::int_bits, ",", From::frac_bits, ",", From::is_signed,
                        ">(raw ", +x.raw(), ") -> Q<", To::int_bits, ",", To::frac_bits, ",",
                        To::is_signed, "> = ", +got.value.raw(),
                        got.saturated ? " (saturated)" : "");
      });
      const Converted<To> checked = x.template convert<To, R, Overflow::checked>();
      f.check(checked.value == got.value && checked.saturated == got.saturated,
              [&] { return describe("checked differs from saturate"); });
    });
  }
}

template <class From, class... Tos>
void check_convert_from(List<Tos...>, std::mt19937_64& rng, Failures& f) {
  (check_convert<From, Tos>(rng, f), ...);
}

template <class... Froms>
void check_convert_all(List<Froms...> formats, std::mt19937_64& rng, Failures& f) {
  (check_convert_from<Froms>(formats, rng, f), ...);
}

TEST_CASE("Q: convert between every pair of formats, every mode", "[fixed_point][q]") {
  std::mt19937_64 rng(kSeed + 12);
  Failures f;
  check_convert_all(Formats{}, rng, f);
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("Q: convert ties and rails", "[fixed_point][q]") {
  using From = Q<3, 4>;  // steps of 1/16
  using To = Q<7, 0>;
  struct Tie {
    int raw;  // in 1/16
    int away, even, floor, trunc;
  };
  const Tie ties[] = {{8, 1, 0, 0, 0},       {-8, -1, 0, -1, 0},   {24, 2, 2, 1, 1},
                      {-24, -2, -2, -2, -1}, {40, 3, 2, 2, 2},     {-40, -3, -2, -3, -2},
                      {56, 4, 4, 3, 3},      {-56, -4, -4, -4, -3}};
  for (const Tie& t : ties) {
    INFO("raw " << t.raw << " / 16");
    const From x = From::from_raw(t.raw);
    CHECK(x.convert<To, Rounding::nearest_away>().value.raw() == t.away);
    CHECK(x.convert<To, Rounding::nearest_even>().value.raw() == t.even);
    CHECK(x.convert<To, Rounding::floor>().value.raw() == t.floor);
    CHECK(x.convert<To, Rounding::toward_zero>().value.raw() == t.trunc);
  }
  // Narrowing to a format whose rails the value crosses only by rounding: 1 - 2^-8 into Q0.7.
  using Fine = Q<0, 8>;
  using Coarse = Q<0, 7>;
  const auto almost_one = Fine::max();  // 255/256
  CHECK(almost_one.convert<Coarse>().saturated);
  CHECK(almost_one.convert<Coarse>().value == Coarse::max());
  CHECK(almost_one.convert<Coarse, Rounding::nearest_even>().saturated);  // 127.5 -> 128
  CHECK(!almost_one.convert<Coarse, Rounding::floor>().saturated);
  CHECK(Fine::min().convert<Coarse>().value == Coarse::min());  // -1 is representable
  CHECK(!Fine::min().convert<Coarse>().saturated);
  // Signed to unsigned: negative values saturate to 0 unless they round to 0.
  CHECK(Q<3, 4>::from_raw(-1).convert<Q<7, 0, false>>().value.raw() == 0);
  CHECK(!Q<3, 4>::from_raw(-1).convert<Q<7, 0, false>>().saturated);
  CHECK(Q<3, 4>::from_raw(-8).convert<Q<7, 0, false>>().saturated);  // -0.5 -> -1
  CHECK(!Q<3, 4>::from_raw(-8).convert<Q<7, 0, false>, Rounding::nearest_even>().saturated);
  // Widening the extremes of 64-bit formats.
  CHECK(Q<63, 0>::min().convert<Q<0, 64, false>>().saturated);
  CHECK(Q<0, 64, false>::max().convert<Q<63, 0>>().value.raw() == 1);  // 1 - 2^-64 -> 1
  CHECK(Q<0, 64, false>::max().convert<Q<63, 0>, Rounding::floor>().value.raw() == 0);
  CHECK(Q<0, 63>::min().convert<Q<63, 0>>().value.raw() == -1);
  CHECK(Q<63, 0>::from_raw(1).convert<Q<0, 64, false>>().saturated);
  CHECK(Q<63, 0>::max().convert<Q<0, 63>>().value == Q<0, 63>::max());
}

// --- add_sat / sub_sat ---------------------------------------------------------------------------

// The exact sum or difference of two raw values, clamped to QT's range. Integer reference: a sum
// of 64-bit values needs 65 bits, more than armhf's long double holds, so overflow of the 64-bit
// intermediate is detected with the compiler's checked arithmetic and means "beyond every rail".
template <class QT>
typename QT::storage_type reference_add_sub(QT a, QT b, bool subtract) {
  using W = std::conditional_t<QT::is_signed, std::int64_t, std::uint64_t>;
  const W x = a.raw(), y = b.raw();
  W exact = 0;
  const bool overflow =
      subtract ? __builtin_sub_overflow(x, y, &exact) : __builtin_add_overflow(x, y, &exact);
  if constexpr (QT::is_signed) {
    if (overflow) return (subtract ? y < 0 : y > 0) ? QT::max_raw : QT::min_raw;
    if (exact < W{QT::min_raw}) return QT::min_raw;
  } else {
    if (overflow) return subtract ? QT::min_raw : QT::max_raw;  // below 0, or 2^64 and beyond
  }
  if (exact > W{QT::max_raw}) return QT::max_raw;
  return static_cast<typename QT::storage_type>(exact);
}

template <class QT>
void check_add_sub(QT a, QT b, Failures& f) {
  const QT sum = add_sat(a, b), difference = sub_sat(a, b);
  f.check(sum.raw() == reference_add_sub(a, b, false) &&
              difference.raw() == reference_add_sub(a, b, true),
          [&] {
            return describe("Q<", QT::int_bits, ",", QT::frac_bits, ",", QT::is_signed, "> ",
                            +a.raw(), " +- ", +b.raw(), " = ", +sum.raw(), ", ", +difference.raw());
          });
}

template <class QT>
void check_add_sub_exhaustive(Failures& f) {
  for (std::int64_t a = QT::min_raw; a <= QT::max_raw; ++a) {
    for (std::int64_t b = QT::min_raw; b <= QT::max_raw; ++b) {
      check_add_sub(QT::from_raw(a), QT::from_raw(b), f);
    }
  }
}

template <class QT>
void check_add_sub_random(std::mt19937_64& rng, Failures& f) {
  for (int n = 0; n < 50000; ++n) {
    check_add_sub(QT::from_raw(random_raw<QT>(rng)), QT::from_raw(random_raw<QT>(rng)), f);
  }
}

TEST_CASE("Q: add_sat and sub_sat saturate at both rails", "[fixed_point][q]") {
  Failures f;
  check_add_sub_exhaustive<Q<3, 4>>(f);
  check_add_sub_exhaustive<Q<2, 4>>(f);
  check_add_sub_exhaustive<Q<4, 4, false>>(f);
  check_add_sub_exhaustive<Q<3, 4, false>>(f);
  std::mt19937_64 rng(kSeed + 13);
  check_add_sub_random<Q<1, 14>>(rng, f);
  check_add_sub_random<Q<8, 24, false>>(rng, f);
  check_add_sub_random<Q<10, 20>>(rng, f);
  check_add_sub_random<Q<31, 32>>(rng, f);
  check_add_sub_random<Q<0, 63>>(rng, f);
  check_add_sub_random<Q<32, 32, false>>(rng, f);
  check_add_sub_random<Q<0, 64, false>>(rng, f);
  BOLO_FX_REQUIRE_NO_FAILURES(f);
  using T = Q<15, 16>;
  CHECK(add_sat(T::max(), T::max()) == T::max());
  CHECK(add_sat(T::min(), T::min()) == T::min());
  CHECK(sub_sat(T::min(), T::max()) == T::min());
  CHECK(sub_sat(T::max(), T::min()) == T::max());
  CHECK(sub_sat(T{}, T::min()) == T::max());  // -(-2^15) does not fit
  using U = Q<0, 64, false>;
  CHECK(add_sat(U::max(), U::epsilon()) == U::max());
  CHECK(sub_sat(U{}, U::epsilon()) == U{});
}

// --- mul_wide and mul ----------------------------------------------------------------------------

template <class A, class B>
void check_mul_wide(A x, B y, Failures& f) {
  const auto p = mul_wide(x, y);
  using P = decltype(p);
  static_assert(P::frac_bits == A::frac_bits + B::frac_bits);
  f.check(as_ld(p.raw()) == as_ld(x.raw()) * as_ld(y.raw()),
          [&] { return describe("mul_wide ", +x.raw(), " * ", +y.raw(), " = ", +p.raw()); });
}

template <class ResultQ, class A, class B>
void check_mul(A x, B y, Failures& f) {
  // Exact when the operands' significant bits sum to at most kLongDoubleDigits.
  const ld exact =
      std::ldexp(as_ld(x.raw()) * as_ld(y.raw()), ResultQ::frac_bits - A::frac_bits - B::frac_bits);
  for_each_rounding([&](auto rc) {
    constexpr Rounding R = decltype(rc)::value;
    const ResultQ got = mul<ResultQ, R>(x, y);
    f.check(matches(expected_raw<ResultQ>(exact, R), got), [&] {
      return describe(name(R), " mul ", +x.raw(), " * ", +y.raw(), " into Q<", ResultQ::int_bits,
                      ",", ResultQ::frac_bits, ",", ResultQ::is_signed, "> = ", +got.raw());
    });
    if constexpr (A::total_bits + B::total_bits <= 64) {
      const auto via_wide = mul_wide(x, y).template convert<ResultQ, R>();
      f.check(via_wide.value == got,
              [&] { return describe("mul differs from mul_wide + convert"); });
    }
  });
}

template <class A, class B>
void check_mul_exhaustive(Failures& f) {
  for (std::int64_t a = A::min_raw; a <= A::max_raw; ++a) {
    for (std::int64_t b = B::min_raw; b <= B::max_raw; ++b) {
      const A x = A::from_raw(a);
      const B y = B::from_raw(b);
      check_mul_wide(x, y, f);
      check_mul<Q<7, 0>>(x, y, f);
      check_mul<Q<3, 4>>(x, y, f);
      check_mul<Q<0, 7>>(x, y, f);
      check_mul<Q<4, 4, false>>(x, y, f);
      check_mul<Q<6, 9>>(x, y, f);
    }
  }
}

TEST_CASE("Q: mul_wide and mul, exhaustive over 8-bit formats", "[fixed_point][q]") {
  Failures f;
  check_mul_exhaustive<Q<3, 4>, Q<3, 4>>(f);
  check_mul_exhaustive<Q<3, 4>, Q<4, 4, false>>(f);
  check_mul_exhaustive<Q<4, 4, false>, Q<2, 4>>(f);
  check_mul_exhaustive<Q<4, 4, false>, Q<0, 8, false>>(f);
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

template <class A, class B, class... Results>
void check_mul_random(std::mt19937_64& rng, Failures& f) {
  for (int n = 0; n < 20000; ++n) {
    // At most kProductBits significant bits each, so the product is an exact long double; the
    // values still reach every bit position, so the 128-bit paths are exercised.
    const A x = A::from_raw(random_raw<A>(rng, kProductBits));
    const B y = B::from_raw(random_raw<B>(rng, kProductBits));
    if constexpr (A::total_bits + B::total_bits <= 64) check_mul_wide(x, y, f);
    (check_mul<Results>(x, y, f), ...);
  }
}

TEST_CASE("Q: mul_wide and mul, random wide formats", "[fixed_point][q]") {
  std::mt19937_64 rng(kSeed + 14);
  Failures f;
  check_mul_random<Q<15, 16>, Q<15, 16>, Q<15, 16>, Q<31, 32>, Q<0, 31>, Q<8, 24, false>>(rng, f);
  check_mul_random<Q<8, 24, false>, Q<8, 24, false>, Q<8, 24, false>, Q<16, 48, false>, Q<1, 14>>(
      rng, f);
  check_mul_random<Q<1, 14>, Q<8, 24, false>, Q<9, 38>, Q<8, 24, false>, Q<1, 14>>(rng, f);
  check_mul_random<Q<0, 31>, Q<0, 31>, Q<1, 62>, Q<0, 31>, Q<0, 15>>(rng, f);
  // Products of up to 128 bits (mul only).
  check_mul_random<Q<31, 32>, Q<31, 32>, Q<31, 32>, Q<63, 0>, Q<0, 63>, Q<32, 32, false>>(rng, f);
  check_mul_random<Q<0, 64, false>, Q<0, 64, false>, Q<0, 64, false>, Q<0, 63>, Q<0, 8, false>>(rng,
                                                                                                f);
  check_mul_random<Q<63, 0>, Q<0, 64, false>, Q<63, 0>, Q<31, 32>, Q<0, 64, false>>(rng, f);
  check_mul_random<Q<64, 0, false>, Q<63, 0>, Q<63, 0>, Q<64, 0, false>>(rng, f);
  BOLO_FX_REQUIRE_NO_FAILURES(f);
}

TEST_CASE("Q: mul ties, signs and rails", "[fixed_point][q]") {
  using T = Q<3, 4>;
  using I = Q<7, 0>;
  // 0.5 * 5 = 2.5, and the signed variants.
  const T half = T::from_raw(8), five = T::from_raw(80), minus_five = T::from_raw(-80);
  CHECK(mul<I, Rounding::nearest_away>(half, five).raw() == 3);
  CHECK(mul<I, Rounding::nearest_even>(half, five).raw() == 2);
  CHECK(mul<I, Rounding::floor>(half, five).raw() == 2);
  CHECK(mul<I, Rounding::toward_zero>(half, five).raw() == 2);
  CHECK(mul<I, Rounding::nearest_away>(half, minus_five).raw() == -3);
  CHECK(mul<I, Rounding::nearest_even>(half, minus_five).raw() == -2);
  CHECK(mul<I, Rounding::floor>(half, minus_five).raw() == -3);
  CHECK(mul<I, Rounding::toward_zero>(half, minus_five).raw() == -2);
  // 0.5 * 7 = 3.5: both nearest modes go to 4.
  const T seven = T::from_raw(112);
  CHECK(mul<I, Rounding::nearest_away>(half, seven).raw() == 4);
  CHECK(mul<I, Rounding::nearest_even>(half, seven).raw() == 4);
  // Rails: (-8)(-8) = 64 does not fit Q3.4; (-8)(7.9375) = -63.5 neither.
  CHECK(mul<T>(T::min(), T::min()) == T::max());
  CHECK(mul<T>(T::min(), T::max()) == T::min());
  CHECK(mul<I>(T::min(), T::max()).raw() == -64);  // -63.5 away from zero
  CHECK(mul<I, Rounding::nearest_even>(T::min(), T::max()).raw() == -64);
  CHECK(mul<I, Rounding::toward_zero>(T::min(), T::max()).raw() == -63);
  // A negative product into an unsigned result.
  CHECK(mul<Q<4, 4, false>>(half, minus_five) == Q<4, 4, false>::min());
  // The widest signed product: (-2^63)(-2^63) = 2^126.
  using W = Q<63, 0>;
  CHECK(mul<W>(W::min(), W::min()) == W::max());
  CHECK(mul<Q<0, 64, false>>(Q<0, 64, false>::max(), Q<0, 64, false>::max()).raw() ==
        std::numeric_limits<std::uint64_t>::max() - 1);  // (1 - 2^-64)^2 = 1 - 2^-63 + 2^-128
}

}  // namespace
}  // namespace bolo::fx::test
