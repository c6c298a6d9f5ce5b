#pragma once
// Floating-point reference of the two-frame corrector (paper Eq. 6), written independently of the
// firmware: whole frames, seconds as doubles, its own rule for when a frame has a usable
// predecessor. The fixed-point firmware is tested against it.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bolo::sim {

// I' = (I - a * I_prev) * g, a = exp(-t_r,prev / tau_c), g = 1 / (1 - exp(-t_e / tau_h)), clamped
// to [0, 65535] but not rounded. An empty `previous` means no carry-over term.
void correct_frame_reference(std::span<const std::uint16_t> current,
                             std::span<const std::uint16_t> previous, double tau_h_s,
                             double tau_c_s, double exposure_s, double previous_readout_s,
                             std::span<double> out);

struct ReferenceFrameInfo {
  std::uint64_t index = 0;
  std::optional<double> t_s;
  std::optional<double> exposure_s;
  std::optional<double> readout_s;
  bool ffc = false;
};

// Streams whole frames through the reference, deciding per frame whether the previous frame is
// a usable predecessor (not the first, no index gap, no time gap > 1.5 nominal periods, time
// increasing, no FFC event).
class ReferenceCorrector {
 public:
  ReferenceCorrector(std::uint32_t width, std::uint32_t height, double tau_h_s, double tau_c_s,
                     std::optional<double> default_exposure_s,
                     std::optional<double> default_readout_s,
                     std::optional<double> nominal_period_s);
  // Returns true when the carry-over term was applied.
  bool process(const ReferenceFrameInfo& info, std::span<const std::uint16_t> frame,
               std::span<double> out);

 private:
  std::uint32_t width_, height_;
  double tau_h_, tau_c_;
  std::optional<double> default_exposure_, default_readout_, nominal_period_;
  std::vector<std::uint16_t> previous_;
  std::optional<ReferenceFrameInfo> previous_info_;
  std::vector<double> intervals_;
};

}  // namespace bolo::sim
