#pragma once
// What the correction reports about each frame, and the interface that receives it while the
// frames are corrected (the --stats file, the summary, a progress bar, tests).

#include <cstdint>

#include "bolo/firmware/two_frame_corrector.hpp"

namespace bolo::correct {

struct FrameStats {
  std::uint64_t frame = 0;
  fw::CarryOver carry_over = fw::CarryOver::first_frame;
  fw::CoefficientStatus coefficient_status = fw::CoefficientStatus::ok;
  double gain = 1.0, carry = 0.0;  // as applied: the pipeline's, or with --float the reference's
  std::uint64_t saturated_low = 0, saturated_high = 0;
  std::uint32_t bad_pixels_replaced = 0, bad_pixels_unrepairable = 0;
  bool reference_disagrees = false;  // --float: the reference judged the predecessor differently
  bool exposure_from_flag = false, readout_from_flag = false;  // else from frames.csv
};

class FrameObserver {
 public:
  virtual ~FrameObserver() = default;
  // Before the first frame: how many frames will come.
  virtual void on_begin(std::uint64_t frames) { (void)frames; }
  // After each frame is corrected (and written), in order, once per frame.
  virtual void on_frame(const FrameStats& stats) = 0;
};

}  // namespace bolo::correct
