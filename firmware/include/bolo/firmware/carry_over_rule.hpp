#pragma once
// When a frame may be corrected against the one before it, as far as their headers tell: the one
// rule for every consumer of frame pairs (TwoFrameCorrector, the VO's carry-over chain).

#include <cstdint>

#include "bolo/firmware/two_frame_corrector.hpp"

namespace bolo::fw {

// A shutter event, a skipped frame counter, time that stood still or went back, or an interval
// over 1.5 frame periods (period_ns 0: unknown, not checked) break the chain; else `applied`. The
// frames' sizes, and whether the predecessor exists and arrived whole, are the caller's to check.
CarryOver carry_over_between(const FrameHeader& previous, const FrameHeader& current, std::uint64_t period_ns);

}  // namespace bolo::fw
