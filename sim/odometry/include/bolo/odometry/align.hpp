#pragma once
// Trajectory alignment and fits for evaluation: timestamp association, Umeyama's closed-form
// similarity (Sim(3)) between two point sets, least-squares plane and line fits.

#include <vector>

#include "bolo/odometry/tum.hpp"

namespace bolo::odo {

// Pairs (estimate index, truth index) whose times differ by at most `tolerance_s` (nearest).
struct Association {
  std::vector<std::size_t> estimate, truth;
};
Association associate(const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
                      double tolerance_s);

// truth ~ s * R * estimate + t
struct Similarity {
  double s = 1;
  vo::Mat3 R = vo::Mat3::Identity();
  vo::Vec3 t = vo::Vec3::Zero();
  vo::Vec3 apply(const vo::Vec3& p) const { return s * (R * p) + t; }
};
// Needs at least 3 pairs; `with_scale` false gives SE(3).
Similarity umeyama(const std::vector<vo::Vec3>& from, const std::vector<vo::Vec3>& to, bool with_scale);

struct Fit {
  double rmse = 0, std = 0;  // of the orthogonal distances
  std::size_t count = 0;
};
Fit plane_fit(const std::vector<vo::Vec3>& points);
Fit line_fit(const std::vector<vo::Vec3>& points);

}  // namespace bolo::odo
