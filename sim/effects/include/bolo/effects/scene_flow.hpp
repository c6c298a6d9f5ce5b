#pragma once
// How far the simulation input moves from one frame to the next, per pixel, and the input's rate
// of change over an exposure along that motion: what a frame difference smears into a band as
// wide as the frame-to-frame sweep of a sharp edge.

#include <vector>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// Fills d.input_flow_dy/dx: input[n + 1](x) ~
// input[n](x - (dy, dx)) in whole pixels, 0 where nothing changes and in the last frame. Block
// matching, coarse to fine (a search up to `max_shift` pixels on 2x2 bins, 10x10-pixel windows,
// then +-1 pixel at full resolution on 7x7 windows), only where the input changes; ties go to
// the smallest displacement.
void fill_input_flow(DiagnoseData& d, int max_shift = 12);

// The flow from frame n to n + 1 to a fraction of a pixel (pixels per frame, P each): the whole-
// pixel flow above refined by a parabola through the matching cost one pixel either side in each
// axis. 0 where the input does not change; needs fill_input_flow first (else all 0).
void subpixel_input_flow(const DiagnoseData& d, int n, std::vector<float>& dy, std::vector<float>& dx);

// d/d(delay) of the input averaged over an exposure that starts `delay` late: the input's change
// over one exposure along the flow, divided by the exposure, (input[n](x - f v) - input[n](x)) /
// t_e with f = t_e / frame period; carried through the two-frame response of unit gain,
// s_n = c s_{n-1} + (1 - c) u_n with c = exp(-readout / tau_c), like the baseline. Input units
// per second, N*P; false (out empty) without flow, exposures or tau_c.
bool delay_response(const DiagnoseData& d, double tau_c, std::vector<float>& out);

}  // namespace bolo::diag
