#pragma once
// Continuous-time microbolometer response, per pixel, exact for an input that is constant over
// each sub-step of an exposure (so motion within a frame is handled by sampling the scene at
// sub-steps). Within frame i:
//   exposure (length t_e, K sub-steps of d = t_e / K): the heating part h follows
//       dh/dt = (u(t) - h) / tau_h from h = 0, i.e. h_k = h_{k-1} e^{-d/tau_h} + u_k (1 - e^{-d/tau_h});
//   reading:  y_i = s_i + h_K, where s_i is what is left of the previous reading;
//   readout (length t_r): s_{i+1} = y_i e^{-t_r / tau_c}.
// With a constant input this is exactly the paper's two-frame model
//   y_i = y_{i-1} e^{-t_r,i-1 / tau_c} + u_i (1 - e^{-t_e,i / tau_h}),
// which makes it the baseline the effect modules of the simulator extend. With t_e = t_r = T and
// tau_h = tau_c it is a first-order lag through the whole period T, read at its end (heating from
// zero and the decay of the previous reading, superposed): the simulator's PixelLag::continuous. Time constants may be
// given per pixel (for effects such as tau_spread).

#include <cstdint>
#include <span>
#include <vector>

namespace bolo::sim {

class BolometerArray {
 public:
  BolometerArray(std::uint32_t width, std::uint32_t height, double tau_h_s, double tau_c_s);
  // Per-pixel time constants (row-major, width * height, seconds, all > 0).
  BolometerArray(std::uint32_t width, std::uint32_t height, std::vector<double> tau_h_s,
                 std::vector<double> tau_c_s);

  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

  // One frame. `substeps` holds K >= 1 steady-state images (row-major floats) sampled at the
  // centres of K equal parts of the exposure. `reading` receives y_i. The state then cools over
  // `readout_s`, ready for the next frame.
  void expose(std::span<const std::span<const float>> substeps, double exposure_s,
              double readout_s, std::span<double> reading);
  // A shutter event or power-up: nothing of earlier frames is left.
  void reset();
  // As if the pixels had looked at `input` for ever with this timing: the next frame of the same
  // input reads the steady state u (1 - e^{-t_e/tau_h}) / (1 - e^{-t_r/tau_c}).
  void settle(std::span<const float> input, double exposure_s, double readout_s);
  // New time constants from the next frame on: one value each, or width * height values.
  void set_time_constants(std::vector<double> tau_h_s, std::vector<double> tau_c_s);

 private:
  std::uint32_t width_, height_;
  std::vector<double> tau_h_, tau_c_;  // one entry each when uniform
  std::vector<double> residual_;       // s_i per pixel
  std::vector<double> heat_;           // h per pixel during an exposure
};

}  // namespace bolo::sim
