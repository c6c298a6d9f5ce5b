#pragma once
// The window bundle adjustment and its marginalisation prior (window_ba.cpp).

#include <cstddef>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "bolo/vo/config.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

struct MapCore;
struct TrackingReference;

inline constexpr std::uint32_t kMaxBaParams = 8 * kMaxKeyframes;
// Per window point in the BA scratch (MapCore::scratch): H_rr, g_r, backup inverse depth, coupling
// to kf params, the host pattern and two counts (window_ba.cpp lays the row out).
inline constexpr std::size_t kBaStride = 3 + kMaxBaParams + kPattern + 2;
using BaMatrix = Eigen::Matrix<double, kMaxBaParams, kMaxBaParams>;
using BaVector = Eigen::Matrix<double, kMaxBaParams, 1>;

// The BA's Gauss-Newton system on the keyframe parameters.
struct BaSystem {
  std::span<std::uint32_t> index;  // per window point
  BaMatrix H;
  BaVector b;
  BaMatrix prior_H;  // the marginalisation prior's Hessian in the BA's window order
};

// What retired keyframes left on the window: a Gaussian on the keyframe parameters, 8 a slot, in
// the BA's half-gradient convention (energy/2 ~ b.d + d.H.d/2), d the parameters' offsets from the
// linearisation point (left pose increment, a, b).
struct MarginalPrior {
  BaMatrix H = BaMatrix::Zero();
  BaVector b = BaVector::Zero();
  Se3 T_cw[kMaxKeyframes];
  double a[kMaxKeyframes] = {}, b_offset[kMaxKeyframes] = {};
  bool in_prior[kMaxKeyframes] = {};  // the slot's rows are not all zero
  bool set = false;
};

// Adjusts the window's keyframe poses (and, in affine, brightness) and active inverse depths with
// the prior, drops the points that fit badly, and marks the tracking reference stale (the frame
// loop then follows the newest keyframe's refined pose and brightness).
void window_bundle_adjustment(MapCore& s, BaSystem& ba, const MarginalPrior& prior, TrackingReference& ref);
// Before the oldest keyframe leaves the window: its points' observations, the points and then
// its own parameters eliminated, join the marginalisation prior on the remaining keyframes.
void marginalise_oldest_keyframe(MapCore& s, BaSystem& ba, MarginalPrior& prior);
void clear_marginal_prior(MarginalPrior& prior);
// The prior's energy at the current keyframe parameters, in the photometric energy's units
// (0 without a prior); exposed for tests.
double marginal_prior_energy(const MapCore& s, const MarginalPrior& prior);
// The window's robust photometric energy at the current parameters, with the Gauss-Newton system
// of the keyframe parameters (before the points are eliminated) left in ba.H (lower and upper
// blocks) and ba.b; keyframe k's 8 parameters (left pose increment, a, b) start at 8 * its
// place in s.order. What window_bundle_adjustment() solves, less the marginalisation prior;
// exposed for tests.
double window_system(MapCore& s, BaSystem& ba);

}  // namespace bolo::vo
