#pragma once
// Residual that lives where the simulated input changes.

#include <vector>

#include "bolo/diagnose/diagnose.hpp"

namespace bolo::diag {

// The residual's variance where the baseline changes from the previous frame (moving edges and
// the frames after them) against where it holds still. An excess well beyond chance, and a
// visible share of the noise floor, is a transient response the model lacks (motion within the
// exposure, a timing, a second time constant) that no finding took. False without one, or
// without a scene (the static-camera background changes nowhere).
bool moving_edge_residual(const DiagnoseData& d, const std::vector<float>& r, double noise_floor, Unexplained& u);

}  // namespace bolo::diag
