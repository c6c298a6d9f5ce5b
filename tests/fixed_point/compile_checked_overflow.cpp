// Built by ctest (not linked): with BOLO_FX_OUT_OF_RANGE=0 it must compile, with =1 it must not,
// because Overflow::checked makes an out-of-range constant ill-formed. The pair shows the failure
// comes from the overflow and nothing else.
#include "bolo/fixed_point/q.hpp"

#ifndef BOLO_FX_OUT_OF_RANGE
#error "define BOLO_FX_OUT_OF_RANGE to 0 or 1"
#endif

namespace {
using bolo::fx::kDefaultRounding;
using bolo::fx::Overflow;
using bolo::fx::Q;

constexpr double kValue = BOLO_FX_OUT_OF_RANGE ? 2.5 : 1.5;  // Q1.14 holds [-2, 2)
constexpr auto kConstant = Q<1, 14>::from_double<kDefaultRounding, Overflow::checked>(kValue);
static_assert(kConstant.value.raw() == 24576);
}  // namespace
