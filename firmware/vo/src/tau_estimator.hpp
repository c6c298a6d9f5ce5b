#pragma once
// The tau estimator (tau_estimator.cpp, ir modes): the bolometer time constants from the
// carry-over between frames and from shutter events, and the stuck-pixel check it relies on.

#include <cstdint>
#include <span>

#include "bolo/vo/carry_model.hpp"

namespace bolo::vo {

struct CurrentFrame;
struct MapCore;
struct MotionModel;

struct TauEstimator {
  Tau tau;  // the estimate
  double sab = 0, sbb = 0, sbbr = 0;  // the sums it is solved from
  double sbb_total = 0;  // sbb before the noise correction
  // Each frame's (sab, sbb) contribution's second moments, forgotten at the square of sab's
  // rate: the frame-to-frame scatter the estimate's standard error is read from.
  double scatter_aa = 0, scatter_ab = 0, scatter_bb = 0;
  bool solved = false;  // the estimate has come from the sums (not only the starting tau)
  std::uint32_t shutter_measurements = 0;  // shutter events whose step response gave tau
  double shutter_tau = 0;                  // their running mean (seconds)
  double shutter_tau_var = 0;              // their spread about it, weighted alike (seconds^2)
  std::span<std::uint8_t> unchanged_frames;  // per pixel: checks its raw value stayed the same
  bool stuck_check_due = false;              // the check runs every other frame
  std::uint32_t stuck_pixels = 0;            // found by the last check (none: no point is tested)
};

// Refines the estimate from the carry-over of the window's points between the current frame and
// the one before (both posed; pixel_noise_var: the noise estimate, counts^2).
void refine_tau(TauEstimator& est, const MapCore& map, const CurrentFrame& f, const MotionModel& motion,
                double pixel_noise_var);
// A shutter event's step response gave `tau_s` (0: none in range): from the first such
// measurement on, tau follows them and the carry-over pairs no longer move it. Returns whether it
// was taken (one far from the current estimate is not).
bool take_shutter_measurement(TauEstimator& t, double tau_s);
// tau_c's standard error (seconds) in the estimate as it stands: from the spread of the shutter
// events' measurements once two were taken, otherwise from the frame-to-frame scatter of the
// carry-over fits (a ratio estimator's delta-method variance), or 0 while neither has moved the
// estimate from its start. A statistical error: the bias of the pairs on smooth images
// (docs/odometry-study.md, "τ") is not in it.
double tau_standard_error(const TauEstimator& est);
// Per pixel, the consecutive checks (every other frame) at which its raw value stayed exactly the
// same as the frame before: refine_tau leaves out samples near stuck pixels. Called for every
// frame after the first.
void count_unchanged_frames(TauEstimator& est, const CurrentFrame& f, const MapCore& map);

}  // namespace bolo::vo
