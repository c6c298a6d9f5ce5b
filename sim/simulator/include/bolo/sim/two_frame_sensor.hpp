#pragma once
// The paper's discrete microbolometer model run forward: each frame reads
//   I_i = I_ss,i * (1 - exp(-t_e,i / tau_h)) + I_{i-1} * exp(-t_r,i-1 / tau_c)
// so the two-frame corrector, given the same constants, recovers I_ss. The baseline a fuller
// continuous-time simulator must reproduce as its special case.

#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <vector>

namespace bolo::sim {

// Eq. 6's coefficients for one frame: `heat`, the share of its steady-state input a pixel reaches
// in an exposure of t_e, 1 - exp(-t_e / tau_h); `carry`, the share of the previous reading left
// after the readout t_r that followed it, exp(-t_r / tau_c). The one definition the simulator and
// the diagnosis baseline share.
struct FrameCoefficients {
  double heat = 0.0, carry = 0.0;
};
FrameCoefficients frame_coefficients(double exposure_s, double previous_readout_s, double tau_h_s, double tau_c_s);

struct SensorTiming {
  double exposure_s = 0.0;  // t_e of this frame
  double readout_s = 0.0;   // t_r that follows it
};

class TwoFrameSensor {
 public:
  struct Options {
    double tau_h_s = 0.012;
    double tau_c_s = 0.012;
    double noise_counts = 0.0;   // white temporal noise, standard deviation in counts
    std::uint32_t bits = 14;     // output quantisation (clamped to [0, 2^bits - 1])
    std::uint64_t seed = 1;
  };
  TwoFrameSensor(std::uint32_t width, std::uint32_t height, Options options);

  // One frame: scene in steady-state counts in, raw counts out. `reset` starts a new chain (first
  // frame, after a shutter event): the previous frame's carry-over is dropped.
  void expose(std::span<const float> scene, SensorTiming timing, bool reset,
              std::span<std::uint16_t> out);

 private:
  std::uint32_t width_, height_;
  Options options_;
  std::vector<double> previous_;  // the previous frame's noiseless analogue value
  std::optional<double> previous_readout_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
};

}  // namespace bolo::sim
