#pragma once
// Trajectory alignment and fits for evaluation: timestamp association, Umeyama's closed-form
// similarity (Sim(3)) between two point sets, per tracking segment as well, least-squares plane
// and line fits.

#include <optional>
#include <string>
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

// The tracking segment of each frame, from the VO's state names (stats.csv's `state`): a
// restart (an "initialising" frame after a "tracking" one) begins the next segment, whose map has
// its own scale and origin.
std::vector<std::size_t> tracking_segments(const std::vector<std::string>& states);

// Runs of pose pairs (from[k], to[k]) with the same segment id, each aligned on its own.
struct SegmentAlignment {
  std::size_t begin = 0, end = 0;        // [begin, end) into the pairs
  std::optional<Similarity> similarity;  // none below 3 pairs
  double squared_error = 0;              // summed over its pairs after its own alignment
};
std::vector<SegmentAlignment> align_segments(const std::vector<vo::Vec3>& from, const std::vector<vo::Vec3>& to,
                                             const std::vector<std::size_t>& segment_of);

struct Fit {
  double rmse = 0, std = 0;  // of the orthogonal distances
  std::size_t count = 0;
};
Fit plane_fit(const std::vector<vo::Vec3>& points);
Fit line_fit(const std::vector<vo::Vec3>& points);

}  // namespace bolo::odo
