#pragma once
// Where the baseline's recursion (FrameSteps, data.hpp) starts afresh and from what level: the
// rule the baseline's response (baseline.cpp), its derivative with respect to ln tau
// (two_frame_derivative.hpp) and the within-exposure delay response (scene_flow.cpp) follow.

#include <cstddef>
#include <vector>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

// The first frame and frames.csv's flagged shutter frames start afresh; every other frame is
// carried over from the one before.
inline bool restarts(const DiagnoseData& d, int n) { return n == 0 || d.flagged_event[std::size_t(n)]; }

// How frame n starts: carried over; the first frame from its own input (settled on it); a
// flagged shutter frame from the input's mean level (the shutter is at the camera's temperature).
struct FrameStart {
  enum Kind { carried, own_input, shutter } kind = carried;
  double level = 0;  // the shutter's level, in input units
};

inline FrameStart frame_start(const DiagnoseData& d, const std::vector<float>& input, int n) {
  if (!restarts(d, n)) return {};
  if (n == 0) return {FrameStart::own_input, 0.0};
  const std::size_t P = d.shape.pixels();
  const float* u = d.frame(input, n);
  double sum = 0;
  for (std::size_t p = 0; p < P; ++p) sum += u[p];
  return {FrameStart::shutter, sum / double(P)};
}

}  // namespace bolo::diag
