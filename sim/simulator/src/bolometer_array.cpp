#include "bolo/sim/bolometer_array.hpp"

#include "bolo/sim/two_frame_sensor.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bolo::sim {
namespace {

void check_taus(const std::vector<double>& taus, const char* name) {
  for (double t : taus)
    if (!(t > 0) || !std::isfinite(t))
      throw std::invalid_argument(std::string("BolometerArray: ") + name +
                                  " must be finite and > 0, got " + std::to_string(t));
}

}  // namespace

BolometerArray::BolometerArray(std::uint32_t width, std::uint32_t height, double tau_h_s,
                               double tau_c_s)
    : BolometerArray(width, height, std::vector<double>{tau_h_s}, std::vector<double>{tau_c_s}) {}

BolometerArray::BolometerArray(std::uint32_t width, std::uint32_t height,
                               std::vector<double> tau_h_s, std::vector<double> tau_c_s)
    : width_(width),
      height_(height),
      residual_(std::size_t{width} * height, 0.0),
      heat_(residual_.size(), 0.0) {
  set_time_constants(std::move(tau_h_s), std::move(tau_c_s));
}

void BolometerArray::set_time_constants(std::vector<double> tau_h_s, std::vector<double> tau_c_s) {
  const std::size_t n = residual_.size();
  if ((tau_h_s.size() != 1 && tau_h_s.size() != n) || (tau_c_s.size() != 1 && tau_c_s.size() != n))
    throw std::invalid_argument("BolometerArray: per-pixel time constants need width*height values");
  check_taus(tau_h_s, "tau_h");
  check_taus(tau_c_s, "tau_c");
  tau_h_ = std::move(tau_h_s);
  tau_c_ = std::move(tau_c_s);
}

void BolometerArray::reset() { std::fill(residual_.begin(), residual_.end(), 0.0); }

void BolometerArray::settle(std::span<const float> input, double exposure_s, double readout_s) {
  if (input.size() != residual_.size())
    throw std::invalid_argument("BolometerArray::settle: input size differs");
  for (std::size_t p = 0; p < residual_.size(); ++p) {
    const auto [heat, carry] = frame_coefficients(exposure_s, readout_s, tau_h_[tau_h_.size() == 1 ? 0 : p],
                                                  tau_c_[tau_c_.size() == 1 ? 0 : p]);
    // Without cooling (t_r = 0) there is no steady state; start from nothing instead.
    residual_[p] = carry < 1.0 - 1e-12 ? input[p] * heat / (1.0 - carry) * carry : 0.0;
  }
}

void BolometerArray::expose(std::span<const std::span<const float>> substeps, double exposure_s,
                            double readout_s, std::span<double> reading) {
  const std::size_t n = residual_.size();
  if (substeps.empty()) throw std::invalid_argument("BolometerArray::expose: no sub-steps");
  for (const auto& s : substeps)
    if (s.size() != n) throw std::invalid_argument("BolometerArray::expose: sub-step size differs");
  if (reading.size() != n) throw std::invalid_argument("BolometerArray::expose: reading size differs");
  if (!(exposure_s > 0) || !(readout_s >= 0))
    throw std::invalid_argument("BolometerArray::expose: exposure must be > 0, readout >= 0");

  const double d = exposure_s / static_cast<double>(substeps.size());
  const bool uniform_h = tau_h_.size() == 1, uniform_c = tau_c_.size() == 1;
  const double keep_h = std::exp(-d / tau_h_[0]);
  const double cool = std::exp(-readout_s / tau_c_[0]);
  std::fill(heat_.begin(), heat_.end(), 0.0);
  for (const auto& u : substeps) {
    for (std::size_t p = 0; p < n; ++p) {
      const double keep = uniform_h ? keep_h : std::exp(-d / tau_h_[p]);
      heat_[p] = heat_[p] * keep + u[p] * (1.0 - keep);
    }
  }
  for (std::size_t p = 0; p < n; ++p) {
    reading[p] = residual_[p] + heat_[p];
    residual_[p] = reading[p] * (uniform_c ? cool : std::exp(-readout_s / tau_c_[p]));
  }
}

}  // namespace bolo::sim
