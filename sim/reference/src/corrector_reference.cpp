#include "bolo/sim/corrector_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bolo::sim {

void correct_frame_reference(std::span<const std::uint16_t> current,
                             std::span<const std::uint16_t> previous, double tau_h_s,
                             double tau_c_s, double exposure_s, double previous_readout_s,
                             std::span<double> out) {
  if (out.size() != current.size() || (!previous.empty() && previous.size() != current.size()))
    throw std::invalid_argument("correct_frame_reference: frame sizes differ");
  const double g = 1.0 / (1.0 - std::exp(-exposure_s / tau_h_s));
  const double a = previous.empty() ? 0.0 : std::exp(-previous_readout_s / tau_c_s);
  for (std::size_t i = 0; i < current.size(); ++i) {
    const double prev = previous.empty() ? 0.0 : previous[i];
    const double value = (current[i] - a * prev) * g;
    out[i] = std::clamp(value, 0.0, 65535.0);
  }
}

ReferenceCorrector::ReferenceCorrector(std::uint32_t width, std::uint32_t height, double tau_h_s,
                                       double tau_c_s, std::optional<double> default_exposure_s,
                                       std::optional<double> default_readout_s,
                                       std::optional<double> nominal_period_s)
    : width_(width),
      height_(height),
      tau_h_(tau_h_s),
      tau_c_(tau_c_s),
      default_exposure_(default_exposure_s),
      default_readout_(default_readout_s),
      nominal_period_(nominal_period_s) {
  if (!(tau_h_s > 0) || !(tau_c_s > 0))
    throw std::invalid_argument("ReferenceCorrector: time constants must be > 0");
}

bool ReferenceCorrector::process(const ReferenceFrameInfo& info,
                                 std::span<const std::uint16_t> frame, std::span<double> out) {
  const std::size_t pixels = std::size_t{width_} * height_;
  if (frame.size() != pixels || out.size() != pixels)
    throw std::invalid_argument("ReferenceCorrector: frame size differs from the configuration");

  bool usable = previous_info_.has_value() && !info.ffc &&
                info.index == previous_info_->index + 1;
  if (usable && info.t_s && previous_info_->t_s) {
    const double interval = *info.t_s - *previous_info_->t_s;
    double period = nominal_period_.value_or(0.0);
    if (!nominal_period_ && !intervals_.empty()) {
      std::vector<double> sorted = intervals_;
      std::sort(sorted.begin(), sorted.end());
      period = sorted[sorted.size() / 2];
    }
    if (interval <= 0 || (period > 0 && interval > 1.5 * period)) usable = false;
  }
  if (previous_info_ && info.t_s && previous_info_->t_s && *info.t_s > *previous_info_->t_s) {
    intervals_.push_back(*info.t_s - *previous_info_->t_s);
    if (intervals_.size() > 8) intervals_.erase(intervals_.begin());
  }

  const std::optional<double> exposure = info.exposure_s ? info.exposure_s : default_exposure_;
  std::optional<double> previous_readout;
  if (previous_info_)
    previous_readout = previous_info_->readout_s ? previous_info_->readout_s : default_readout_;
  if (!previous_readout) usable = false;

  bool applied = false;
  if (!exposure) {
    std::transform(frame.begin(), frame.end(), out.begin(),
                   [](std::uint16_t v) { return static_cast<double>(v); });
  } else if (usable) {
    correct_frame_reference(frame, previous_, tau_h_, tau_c_, *exposure, *previous_readout, out);
    applied = true;
  } else {
    correct_frame_reference(frame, {}, tau_h_, tau_c_, *exposure, 0.0, out);
  }
  previous_.assign(frame.begin(), frame.end());
  previous_info_ = info;
  return applied;
}

}  // namespace bolo::sim
