#pragma once
// Arithmetic the tracker, initialiser, depth search and window BA share: the residual pattern,
// camera scaling per pyramid level, robust weights and the Hessian updates.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "bolo/vo/config.hpp"

namespace bolo::vo {

// Pattern offsets in pixels (own choice: a spread diamond that samples both gradient directions).
inline constexpr float kPatternX[kPattern] = {0, 2, -2, 0, 0, 1, -1, 1};
inline constexpr float kPatternY[kPattern] = {0, 0, 0, 2, -2, 1, -1, -1};

struct Scaled {
  float fx, fy, cx, cy;
};
inline Scaled camera_at(const Camera& c, std::uint32_t level) {
  const float s = 1.0f / static_cast<float>(1u << level);
  return {c.fx * s, c.fy * s, (c.cx + 0.5f) * s - 0.5f, (c.cy + 0.5f) * s - 0.5f};
}
// H += w v v^T on the upper triangle, with Eigen's rankUpdate's arithmetic (a column at a time,
// w v_c first) but inline: its out-of-line call per residual was a quarter of the initialiser's
// instructions.
template <int N>
inline void add_weighted_outer_upper(Eigen::Matrix<double, N, N>& H, const Eigen::Matrix<double, N, 1>& v, double w) {
  for (int c = 0; c < N; ++c) {
    const double a = w * v[c];
    for (int r = 0; r <= c; ++r) H(r, c) += a * v[r];
  }
}

// The upper median of v[0 .. n) (0 when n is 0); reorders v.
inline float upper_median(float* v, std::size_t n) {
  if (n == 0) return 0.0f;
  std::nth_element(v, v + n / 2, v + n);
  return v[n / 2];
}
// The tracker's outlier cut on a point's pattern energy at a pyramid level (tracker.cpp); coarse
// levels start far from the optimum and cut more loosely.
inline float tracking_cutoff(float huber, std::uint32_t level) {
  return static_cast<float>(kPattern) * huber * huber * (level > 0 ? 12.0f : 6.0f);
}
inline float huber_weight(float r, float k) {
  const float a = r < 0 ? -r : r;
  return a <= k ? 1.0f : k / a;
}

// A pattern's residuals against a reference pattern seen with a gain and offset,
// r = value - (gain (reference - reference_offset) + offset), their Huber-and-gradient weights
// and robust energy (summed in pattern order), four pattern pixels at a time (lane by lane the
// arithmetic of huber_weight()). value, gx, gy, r, w: 16-byte aligned, kPattern long.
inline float pattern_residuals(const float* value, const float* gx, const float* gy, const float* reference,
                               float gain, float reference_offset, float offset, float hub, float c2, float* r,
                               float* w) {
  alignas(16) float terms[kPattern];
  for (std::uint32_t h = 0; h < kPattern; h += 4) {
    using A = Eigen::Map<Eigen::Array4f, Eigen::Aligned16>;
    using C = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
    const Eigen::Array4f rr = C(value + h) - (gain * (Eigen::Map<const Eigen::Array4f>(reference + h) - reference_offset) + offset);
    const Eigen::Array4f ra = rr.abs();
    const Eigen::Array4f hw = (ra <= hub).select(Eigen::Array4f::Ones(), hub / ra);
    const Eigen::Array4f gxh = C(gx + h), gyh = C(gy + h);
    A(r + h) = rr;
    A(w + h) = hw * c2 / (c2 + gxh * gxh + gyh * gyh);
    A(terms + h) = hw * rr * rr * (2.0f - hw);
  }
  float energy = 0;
  for (std::uint32_t j = 0; j < kPattern; ++j) energy += terms[j];
  return energy;
}

// A point's pose block D S D^T, D = [du dv] (the centre pixel's projection Jacobian, 6 x 2) and
// S = [sxx sxy; sxy syy] (its pattern's weighted gradient structure), added to the upper triangle
// of H's leading 6 x 6 as two products: H(q, e) += du[q] m0[e] + dv[q] m1[e].
template <typename Matrix>
inline void add_pose_block_upper(Matrix& H, const float* du, const float* dv, float sxx, float sxy, float syy) {
  float m0[6], m1[6];
  for (int q = 0; q < 6; ++q) m0[q] = sxx * du[q] + sxy * dv[q], m1[q] = sxy * du[q] + syy * dv[q];
  for (int q = 0; q < 6; ++q)
    for (int e = q; e < 6; ++e) H(q, e) += du[q] * m0[e] + dv[q] * m1[e];
}

}  // namespace bolo::vo
