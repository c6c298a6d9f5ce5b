#pragma once
// Per-frame coefficients of the two-frame corrector (paper Eq. 6):
//   I'_i = (I_i - a * I_{i-1}) * g,   a = exp(-t_r,i-1 / tau_c),   g = 1 / (1 - exp(-t_e,i / tau_h))
// expanded to I'_i = G * I_i - A * I_{i-1} with G = g and A = a * g, both unsigned Q8.24 so the
// per-pixel kernel is two u16 x u32 -> u64 products.

#include <cstdint>

namespace bolo::fw {

inline constexpr unsigned kCoefficientFractionBits = 24;
// g must stay below 2^8 so G fits 32 bits: t_e / tau_h >= ~0.0039.
inline constexpr std::uint64_t kMaxCoefficientQ24 = 0xFFFFFFFFu;

struct TimeConstants {
  std::uint32_t heating_ns = 0;  // tau_h
  std::uint32_t cooling_ns = 0;  // tau_c
};

struct CorrectorCoefficients {
  std::uint32_t gain_q24 = 1u << kCoefficientFractionBits;  // G = g
  std::uint32_t carry_q24 = 0;                              // A = a * g
};

enum class CoefficientStatus : std::uint8_t {
  ok,
  zero_time_constant,  // tau_h or tau_c is 0
  zero_exposure,       // t_e is 0: g is infinite
  gain_out_of_range,   // t_e / tau_h so small that g >= 256
};

// `exposure_ns` is this frame's t_e, `previous_readout_ns` the t_r that followed the previous
// frame. Integer-only and bit-exact on every target.
CoefficientStatus compute_coefficients(TimeConstants tau, std::uint32_t exposure_ns,
                                       std::uint32_t previous_readout_ns,
                                       CorrectorCoefficients& out);

// Coefficients for a frame with no usable predecessor: I' = g * I (no carry-over term).
CoefficientStatus compute_gain_only(TimeConstants tau, std::uint32_t exposure_ns,
                                    CorrectorCoefficients& out);

const char* to_string(CoefficientStatus status);

}  // namespace bolo::fw
