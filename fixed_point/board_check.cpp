// Compiles every fixed_point header with the board's flags (-fno-exceptions -fno-rtti -Werror
// -Wconversion -Wsign-conversion -Wshadow ...) and instantiates representative templates, so a
// header that only builds on the host fails here first. Nothing in this file is called.

#include "bolo/fixed_point/exp_table.hpp"
#include "bolo/fixed_point/q.hpp"
#include "bolo/fixed_point/rounding.hpp"
#include "bolo/fixed_point/storage.hpp"
#include "bolo/fixed_point/wide.hpp"

namespace bolo::fx {

// Every rounding mode of the integer helpers.
template std::int64_t shift_right<Rounding::nearest_away>(std::int64_t, unsigned);
template std::int64_t shift_right<Rounding::nearest_even>(std::int64_t, unsigned);
template std::int64_t shift_right<Rounding::floor>(std::int64_t, unsigned);
template std::int64_t shift_right<Rounding::toward_zero>(std::int64_t, unsigned);
template std::uint64_t shift_right<Rounding::nearest_away>(std::uint64_t, unsigned);
template std::uint64_t shift_right<Rounding::nearest_even>(std::uint64_t, unsigned);
template std::uint64_t shift_right<Rounding::floor>(std::uint64_t, unsigned);
template std::uint64_t shift_right<Rounding::toward_zero>(std::uint64_t, unsigned);
template std::uint64_t divide<Rounding::nearest_away>(std::uint64_t, std::uint64_t);
template std::uint64_t divide<Rounding::nearest_even>(std::uint64_t, std::uint64_t);
template std::int64_t divide<Rounding::floor>(std::int64_t, std::int64_t);
template std::int64_t divide<Rounding::toward_zero>(std::int64_t, std::int64_t);
template std::int8_t saturate<std::int8_t>(std::int64_t);
template std::uint8_t saturate<std::uint8_t>(std::int64_t);
template std::int16_t saturate<std::int16_t>(std::int64_t);
template std::uint16_t saturate<std::uint16_t>(std::int64_t);
template std::int32_t saturate<std::int32_t>(std::int64_t);
template std::uint32_t saturate<std::uint32_t>(std::int64_t);
template std::int64_t saturate<std::int64_t>(std::int64_t);
template std::uint64_t saturate<std::uint64_t>(std::int64_t);

// Formats of every storage width, signed and unsigned, full and narrower than their storage.
template class Q<3, 4>;
template class Q<2, 4>;
template class Q<0, 8, false>;
template class Q<1, 14>;
template class Q<5, 5, false>;
template class Q<8, 24, false>;
template class Q<15, 16>;
template class Q<0, 63>;
template class Q<32, 32, false>;
template class Q<0, 64, false>;
template class Q<63, 0>;

namespace board_check {

using Q1_14 = Q<1, 14>;
using UQ8_24 = Q<8, 24, false>;
using Q15_16 = Q<15, 16>;

Q1_14 add(Q1_14 a, Q1_14 b) { return add_sat(a, b); }
Q1_14 sub(Q1_14 a, Q1_14 b) { return sub_sat(a, b); }
UQ8_24 add(UQ8_24 a, UQ8_24 b) { return add_sat(a, b); }
UQ8_24 sub(UQ8_24 a, UQ8_24 b) { return sub_sat(a, b); }
Q<3, 28> wide(Q1_14 a, Q1_14 b) { return mul_wide(a, b); }
Q<16, 48, false> wide(UQ8_24 a, UQ8_24 b) { return mul_wide(a, b); }
Q<9, 38> wide(Q1_14 a, UQ8_24 b) { return mul_wide(a, b); }
Q1_14 product(Q1_14 a, Q1_14 b) { return mul<Q1_14>(a, b); }
Q15_16 product(Q15_16 a, Q15_16 b) { return mul<Q15_16, Rounding::nearest_even>(a, b); }
UQ8_24 product(UQ8_24 a, Q1_14 b) { return mul<UQ8_24, Rounding::floor>(a, b); }
Converted<Q1_14> narrow(UQ8_24 a) { return a.convert<Q1_14, Rounding::toward_zero>(); }
Converted<UQ8_24> widen(Q1_14 a) { return a.convert<UQ8_24>(); }
Converted<Q15_16> from_integer(std::int32_t v) { return Q15_16::from_int(v); }
Converted<UQ8_24> from_integer(std::uint64_t v) { return UQ8_24::from_int<Overflow::checked>(v); }
std::uint64_t exp_neg(std::uint32_t x_q24) { return exp_neg_q32(x_q24); }

// Constant evaluation, under the same flags.
static_assert(exp_neg_q32(0) == std::uint64_t{1} << 32);
static_assert(shift_right(std::int64_t{-5}, 1) == -3);
static_assert(Q1_14::from_double<Rounding::nearest_away, Overflow::checked>(0.75).value.raw() ==
              12288);
static_assert(mul<Q1_14>(Q1_14::min(), Q1_14::min()) == Q1_14::max());  // (-2)(-2) = 4

// Bit-exactness across targets: a checksum of both tables and of exp_neg_q32 on 4096 inputs spread
// over [0, 23), computed by the compiler for this target. The constant is the x86-64 value; a
// cross build (aarch64, armhf) that disagrees stops here. (Changed when to_q63 stopped rounding
// exp(-7) one unit of 2^-63 too high: no exp_neg_q32 result changed, checked for every input.)
consteval std::uint64_t exp_checksum() {
  std::uint64_t h = 0xcbf29ce484222325u;  // FNV-1a, 64-bit
  const auto mix = [&h](std::uint64_t v) {
    for (int byte = 0; byte < 8; ++byte) {
      h = (h ^ (v & 0xFFu)) * 0x100000001b3u;
      v >>= 8;
    }
  };
  for (const std::uint64_t entry : kExpNegIntegerQ63) mix(entry);
  for (const std::uint64_t entry : kExpNegFractionQ63) mix(entry);
  for (std::uint32_t i = 0; i < 4096; ++i) mix(exp_neg_q32(i * 94'371u + i % 7));
  return h;
}
static_assert(exp_checksum() == 0x9f6a274d9a0d62fcu,
              "exp tables or exp_neg_q32 differ from the x86-64 build");

}  // namespace board_check
}  // namespace bolo::fx
