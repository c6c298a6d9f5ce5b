#include "bolo/firmware/corrector_coefficients.hpp"

#include "bolo/fixed_point/exp_table.hpp"
#include "bolo/fixed_point/rounding.hpp"

namespace bolo::fw {
namespace {

constexpr std::uint64_t kOneQ32 = std::uint64_t{1} << 32;
constexpr unsigned kRatioFractionBits = 24;  // t / tau as Q8.24, the input format of exp_neg_q32

// exp(-t / tau) in Q0.32; ratios of 256 and beyond give 0 (exp(-256) is far below 2^-32).
// The ratio is split as q / 2^24 + d with d < 2^-24: exp(-q / 2^24) comes from the table, and
// exp(-d) = 1 - d to within 2^-49. Without the remainder the error of the ratio (up to 2^-24)
// would be amplified by g in the gain, to ~1e-6 relative for g near 100.
std::uint64_t decay_q32(std::uint32_t t_ns, std::uint32_t tau_ns) {
  const std::uint64_t scaled = std::uint64_t{t_ns} << kRatioFractionBits;
  const std::uint64_t ratio_q24 = scaled / tau_ns;
  if (ratio_q24 > 0xFFFFFFFFu) return 0;
  const std::uint64_t remainder = scaled % tau_ns;  // < tau < 2^32
  const std::uint64_t decay = fx::exp_neg_q32(static_cast<std::uint32_t>(ratio_q24));
  // d in Q0.56 is remainder * 2^32 / tau < 2^32; decay <= 2^32, so decay * d < 2^64.
  const std::uint64_t d_q56 = fx::divide(remainder << 32, std::uint64_t{tau_ns});
  return decay - fx::shift_right(decay * d_q56, 56);
}

}  // namespace

CoefficientStatus compute_gain_only(TimeConstants tau, std::uint32_t exposure_ns,
                                    CorrectorCoefficients& out) {
  if (tau.heating_ns == 0 || tau.cooling_ns == 0) return CoefficientStatus::zero_time_constant;
  if (exposure_ns == 0) return CoefficientStatus::zero_exposure;
  // g = 1 / (1 - exp(-t_e / tau_h)); in Q8.24 that is 2^56 / ((1 - b) in Q0.32).
  const std::uint64_t one_minus_b_q32 = kOneQ32 - decay_q32(exposure_ns, tau.heating_ns);
  if (one_minus_b_q32 == 0) return CoefficientStatus::gain_out_of_range;
  const std::uint64_t gain_q24 =
      fx::divide(std::uint64_t{1} << (32 + kCoefficientFractionBits), one_minus_b_q32);
  if (gain_q24 > kMaxCoefficientQ24) return CoefficientStatus::gain_out_of_range;
  out.gain_q24 = static_cast<std::uint32_t>(gain_q24);
  out.carry_q24 = 0;
  return CoefficientStatus::ok;
}

CoefficientStatus compute_coefficients(TimeConstants tau, std::uint32_t exposure_ns,
                                       std::uint32_t previous_readout_ns,
                                       CorrectorCoefficients& out) {
  CorrectorCoefficients gain_only;
  const CoefficientStatus status = compute_gain_only(tau, exposure_ns, gain_only);
  if (status != CoefficientStatus::ok) return status;
  // A = a * g with a in Q0.32 (<= 2^32) and G < 2^32: the product fits 64 bits.
  const std::uint64_t a_q32 = decay_q32(previous_readout_ns, tau.cooling_ns);
  const std::uint64_t carry_q24 = fx::shift_right(a_q32 * gain_only.gain_q24, 32);
  out.gain_q24 = gain_only.gain_q24;
  out.carry_q24 = static_cast<std::uint32_t>(carry_q24);  // a <= 1, so A <= G
  return CoefficientStatus::ok;
}

const char* to_string(CoefficientStatus status) {
  switch (status) {
    case CoefficientStatus::ok: return "ok";
    case CoefficientStatus::zero_time_constant: return "zero_time_constant";
    case CoefficientStatus::zero_exposure: return "zero_exposure";
    case CoefficientStatus::gain_out_of_range: return "gain_out_of_range";
  }
  return "unknown";
}

}  // namespace bolo::fw
