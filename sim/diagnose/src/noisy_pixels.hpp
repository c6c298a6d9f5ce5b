#pragma once
// Pixels whose residual fluctuates in time far more than the other pixels' do.

#include <vector>

#include "bolo/diagnose/diagnose.hpp"

namespace bolo::diag {

// Isolated pixels with a temporal variance far above the typical pixel's: blinking or
// random-telegraph pixels. Not a catalogue effect (dead_pixels is the opposite: outliers in the
// mean, or too little variance), so it is reported as unexplained. False when there are fewer
// than three such pixels.
bool noisy_pixels(const DiagnoseData& d, const std::vector<float>& r, Unexplained& u);

}  // namespace bolo::diag
