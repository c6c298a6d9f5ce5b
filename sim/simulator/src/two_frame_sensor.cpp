#include "bolo/sim/two_frame_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bolo::sim {

FrameCoefficients frame_coefficients(double exposure_s, double previous_readout_s, double tau_h_s, double tau_c_s) {
  return {1.0 - std::exp(-exposure_s / tau_h_s), std::exp(-previous_readout_s / tau_c_s)};
}

TwoFrameSensor::TwoFrameSensor(std::uint32_t width, std::uint32_t height, Options options)
    : width_(width), height_(height), options_(options),
      previous_(std::size_t{width} * height, 0.0), rng_(options.seed) {
  if (!(options.tau_h_s > 0) || !(options.tau_c_s > 0))
    throw std::invalid_argument("TwoFrameSensor: time constants must be > 0");
  if (options.bits < 1 || options.bits > 16)
    throw std::invalid_argument("TwoFrameSensor: bits must be 1..16");
}

void TwoFrameSensor::expose(std::span<const float> scene, SensorTiming timing, bool reset,
                            std::span<std::uint16_t> out) {
  const std::size_t n = std::size_t{width_} * height_;
  if (scene.size() != n || out.size() != n)
    throw std::invalid_argument("TwoFrameSensor: frame size differs from the sensor");
  const FrameCoefficients k =
      frame_coefficients(timing.exposure_s, previous_readout_.value_or(0.0), options_.tau_h_s, options_.tau_c_s);
  const double heat = k.heat;
  const double carry = (reset || !previous_readout_) ? 0.0 : k.carry;
  const double max_count = std::ldexp(1.0, static_cast<int>(options_.bits)) - 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double analogue = scene[i] * heat + previous_[i] * carry;
    previous_[i] = analogue;
    double reading = analogue;
    if (options_.noise_counts > 0) reading += options_.noise_counts * noise_(rng_);
    out[i] = static_cast<std::uint16_t>(std::clamp(std::round(reading), 0.0, max_count));
  }
  previous_readout_ = timing.readout_s;
}

}  // namespace bolo::sim
