#pragma once
// Motion within the exposure: scene.npy holds the input averaged evenly over each exposure, but a
// pixel weighs its exposure by its response, the late part most.

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// Fills d.exposure_motion: per pixel-frame, the input as the pixel weighs it over the exposure,
// exp(-(t_e - t) / tau_h), less its even average. The input within the exposure is scene.npy's
// frame moved along the measured flow (sub-pixel, the mean of the flows into and out of the frame,
// the frame period the median time step), sampled at 8 points of the exposure. Fills the whole-
// pixel flow first if it is empty. Left empty when the input never moves.
void fill_exposure_motion(DiagnoseData& d, double tau_h);

}  // namespace bolo::diag
