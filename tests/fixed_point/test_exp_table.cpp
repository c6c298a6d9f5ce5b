// exp_neg_q32 against std::exp in long double: exhaustive over x in [0, 1), every 97th input of
// the full 32-bit range, and every table boundary; plus the tables themselves.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "bolo/fixed_point/exp_table.hpp"
#include "fx_test_support.hpp"

namespace bolo::fx::test {
namespace {

// Constant evaluation, and values checked against 50-digit decimal arithmetic.
static_assert(exp_neg_q32(0) == std::uint64_t{1} << 32);           // exp(0) exactly
static_assert(exp_neg_q32(std::uint32_t{1} << 24) == 1580030169);  // e^-1   = 1580030168.702
static_assert(exp_neg_q32(std::uint32_t{1} << 23) == 2605029347);  // e^-0.5 = 2605029347.487
static_assert(exp_neg_q32(std::uint32_t{2} << 24) == 581260615);   // e^-2   = 581260615.496
static_assert(exp_neg_q32(std::uint32_t{10} << 24) == 194991);     // e^-10  = 194991.214
static_assert(exp_neg_q32(std::uint32_t{23} << 24) == 0);          // 0.44 units
static_assert(exp_neg_q32(std::numeric_limits<std::uint32_t>::max()) == 0);
static_assert(kExpNegIntegerQ63[0] == std::uint64_t{1} << 63);
static_assert(kExpNegFractionQ63[0] == std::uint64_t{1} << 63);
static_assert(kExpNegIntegerQ63.size() == kExpNegCutoff && kExpNegFractionQ63.size() == 256);

// x86-64 (80-bit long double, fast) gets x in [0, 1) exhaustively and every 97th input of the
// full range. The boards are slower: armhf (long double = double) and above all aarch64 (binary128
// long double in software) get a shorter exhaustive range and a sparser sweep.
constexpr std::uint32_t kExhaustiveEnd = kLongDoubleDigits == 64   ? (1u << 24)
                                         : kLongDoubleDigits == 53 ? (1u << 22)
                                                                   : (1u << 20);
constexpr std::uint32_t kStride = kLongDoubleDigits == 64   ? 97
                                  : kLongDoubleDigits == 53 ? 997
                                                            : 9973;

// exp(-x_q24 / 2^24) in units of 2^-32.
ld reference_q32(std::uint32_t x_q24) {
  return std::ldexp(std::exp(-std::ldexp(static_cast<ld>(x_q24), -24)), 32);
}

struct ErrorStats {
  ld max_error = 0;
  std::uint32_t worst_input = 0;
  std::uint64_t count = 0;
  std::uint64_t not_nearest = 0;  // results that differ from the correctly rounded value

  void add(std::uint32_t x_q24) {
    const std::uint64_t got = exp_neg_q32(x_q24);
    const ld exact = reference_q32(x_q24);
    const ld error = std::fabs(static_cast<ld>(got) - exact);
    ++count;
    if (static_cast<ld>(got) != std::round(exact)) ++not_nearest;
    if (error > max_error) {
      max_error = error;
      worst_input = x_q24;
    }
  }
};

void report(const char* what, const ErrorStats& s) {
  std::printf(
      "exp_neg_q32 %s: %llu inputs, max |error| = %.6Lf units of 2^-32 at x_q24 = %u, "
      "%llu not correctly rounded\n",
      what, static_cast<unsigned long long>(s.count), s.max_error, s.worst_input,
      static_cast<unsigned long long>(s.not_nearest));
}

TEST_CASE("exp_neg_q32: error <= 2 units of 2^-32 (measured: 1/2 + tiny)", "[fixed_point][exp]") {
  std::printf("exp_neg_q32: exhaustive over x_q24 in [0, %u), then every %u-th input\n",
              kExhaustiveEnd, kStride);
  ErrorStats exhaustive;
  bool monotonic = true;
  std::uint64_t previous = exp_neg_q32(0);
  for (std::uint32_t x = 0; x < kExhaustiveEnd; ++x) {
    exhaustive.add(x);
    const std::uint64_t v = exp_neg_q32(x);
    monotonic = monotonic && v <= previous;
    previous = v;
  }
  report("exhaustive", exhaustive);

  ErrorStats sweep;
  previous = exp_neg_q32(0);
  for (std::uint64_t x = 0; x <= std::numeric_limits<std::uint32_t>::max(); x += kStride) {
    const auto x32 = static_cast<std::uint32_t>(x);
    sweep.add(x32);
    const std::uint64_t v = exp_neg_q32(x32);
    monotonic = monotonic && v <= previous;
    previous = v;
  }
  report("sweep of the full range", sweep);

  // Every table boundary (k, j) and its neighbours, and the cutoff.
  ErrorStats edges;
  for (std::uint64_t k = 0; k <= kExpNegCutoff; ++k) {
    for (std::uint64_t j = 0; j < 256; ++j) {
      const std::uint64_t x = (k << 24) | (j << 16);
      for (std::uint64_t d = 0; d < 3; ++d) {
        if (x + d >= 1 && x + d - 1 <= std::numeric_limits<std::uint32_t>::max()) {
          edges.add(static_cast<std::uint32_t>(x + d - 1));
        }
      }
      edges.add(static_cast<std::uint32_t>(x | 0xFFFFu));
    }
  }
  edges.add(std::numeric_limits<std::uint32_t>::max());
  report("table boundaries", edges);

  for (const ErrorStats* s : {&exhaustive, &sweep, &edges}) {
    CHECK(s->max_error <= 2.0L);          // the documented contract
    CHECK(s->max_error <= 0.5L + 1e-3L);  // what the method achieves: only the final rounding
  }
  CHECK(monotonic);  // exp(-x) never increases with x, also after rounding
}

TEST_CASE("exp tables: entries against long double", "[fixed_point][exp]") {
  // Error of each Q0.63 entry, in units of 2^-32 of a result (2^31 table units).
  ld worst = 0;
  for (std::size_t k = 0; k < kExpNegIntegerQ63.size(); ++k) {
    const ld exact = std::ldexp(std::exp(-static_cast<ld>(k)), 63);
    worst = std::max(worst, std::fabs(static_cast<ld>(kExpNegIntegerQ63[k]) - exact) / 0x1p31L);
  }
  for (std::size_t j = 0; j < kExpNegFractionQ63.size(); ++j) {
    const ld exact = std::ldexp(std::exp(-static_cast<ld>(j) / 256), 63);
    worst = std::max(worst, std::fabs(static_cast<ld>(kExpNegFractionQ63[j]) - exact) / 0x1p31L);
  }
  std::printf("exp tables: max entry error = %.3Le units of 2^-32\n", worst);
  CHECK(worst <= 1e-5L);
  // exp(-23) would round to 0: the cutoff is where the result becomes 0 anyway.
  CHECK(std::ldexp(std::exp(-23.0L), 32) < 0.5L);
  CHECK(std::ldexp(std::exp(-22.0L), 32) > 1.0L);
}

}  // namespace
}  // namespace bolo::fx::test
