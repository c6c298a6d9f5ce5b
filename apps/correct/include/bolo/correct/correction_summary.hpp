#pragma once
// The summary `bolo correct` prints: an observer tallies the frames, print_summary writes it.

#include <cstdint>
#include <ostream>

#include "bolo/correct/correct_recording.hpp"

namespace bolo::correct {

class SummaryTally final : public FrameObserver {
 public:
  void on_frame(const FrameStats& s) override;

  std::uint64_t frames = 0;
  std::uint64_t by_reason[fw::kCarryOverReasons] = {};
  std::uint64_t saturated_low = 0, saturated_high = 0;
  std::uint64_t exposure_from_flag = 0, readout_from_flag = 0;
  std::uint64_t reference_disagreements = 0;
  std::uint64_t bad_replaced = 0, bad_unrepairable = 0;
};

// `request` as the correction ran (OUT as given on the command line).
void print_summary(std::ostream& out, const CorrectRequest& request, const SummaryTally& tally,
                   const CorrectResult& result);

}  // namespace bolo::correct
