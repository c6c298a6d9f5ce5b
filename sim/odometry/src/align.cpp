#include "bolo/odometry/align.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace bolo::odo {

Association associate(const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
                      double tolerance_s) {
  Association a;
  std::size_t j = 0;
  for (std::size_t i = 0; i < estimate.size() && !truth.empty(); ++i) {
    const double t = estimate[i].t;
    while (j + 1 < truth.size() && std::fabs(truth[j + 1].t - t) <= std::fabs(truth[j].t - t)) ++j;
    if (std::fabs(truth[j].t - t) <= tolerance_s) a.estimate.push_back(i), a.truth.push_back(j);
  }
  return a;
}

Similarity umeyama(const std::vector<vo::Vec3>& from, const std::vector<vo::Vec3>& to, bool with_scale) {
  Similarity sim;
  const std::size_t n = std::min(from.size(), to.size());
  if (n < 3) return sim;
  vo::Vec3 mf = vo::Vec3::Zero(), mt = vo::Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) mf += from[i], mt += to[i];
  mf /= static_cast<double>(n), mt /= static_cast<double>(n);
  vo::Mat3 cov = vo::Mat3::Zero();
  double var = 0;
  for (std::size_t i = 0; i < n; ++i) {
    cov += (to[i] - mt) * (from[i] - mf).transpose();
    var += (from[i] - mf).squaredNorm();
  }
  cov /= static_cast<double>(n), var /= static_cast<double>(n);
  Eigen::JacobiSVD<vo::Mat3> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  vo::Mat3 S = vo::Mat3::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
  sim.R = svd.matrixU() * S * svd.matrixV().transpose();
  sim.s = with_scale && var > 0 ? (svd.singularValues().asDiagonal() * S).trace() / var : 1.0;
  sim.t = mt - sim.s * sim.R * mf;
  return sim;
}

std::vector<std::size_t> tracking_segments(const std::vector<std::string>& states) {
  std::vector<std::size_t> segment(states.size(), 0);
  std::size_t current = 0;
  bool posed_in_current = false;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (states[i] == "initialising" && posed_in_current) ++current, posed_in_current = false;
    if (states[i] == "tracking") posed_in_current = true;
    segment[i] = current;
  }
  return segment;
}

std::vector<SegmentAlignment> align_segments(const std::vector<vo::Vec3>& from, const std::vector<vo::Vec3>& to,
                                             const std::vector<std::size_t>& segment_of) {
  std::vector<SegmentAlignment> out;
  for (std::size_t k = 0; k < from.size();) {
    SegmentAlignment seg;
    seg.begin = k;
    while (k < from.size() && segment_of[k] == segment_of[seg.begin]) ++k;
    seg.end = k;
    if (seg.end - seg.begin >= 3) {
      const auto first = static_cast<std::ptrdiff_t>(seg.begin), last = static_cast<std::ptrdiff_t>(seg.end);
      const std::vector<vo::Vec3> f(from.begin() + first, from.begin() + last), t(to.begin() + first, to.begin() + last);
      seg.similarity = umeyama(f, t, true);
      for (std::size_t q = 0; q < f.size(); ++q) seg.squared_error += (seg.similarity->apply(f[q]) - t[q]).squaredNorm();
    }
    out.push_back(seg);
  }
  return out;
}

namespace {
// Distances of points to the best-fitting affine subspace spanned by the top `dims` directions.
Fit subspace_fit(const std::vector<vo::Vec3>& points, int dims) {
  Fit f;
  f.count = points.size();
  if (points.size() < static_cast<std::size_t>(dims + 1)) return f;
  vo::Vec3 mean = vo::Vec3::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  vo::Mat3 cov = vo::Mat3::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  Eigen::JacobiSVD<vo::Mat3> svd(cov, Eigen::ComputeFullU);
  double sum = 0, sum2 = 0;
  for (const auto& p : points) {
    const vo::Vec3 d = p - mean;
    double dist2 = d.squaredNorm();
    for (int k = 0; k < dims; ++k) dist2 -= std::pow(d.dot(svd.matrixU().col(k)), 2);
    const double dist = std::sqrt(std::max(0.0, dist2));
    sum += dist, sum2 += dist * dist;
  }
  const double n = static_cast<double>(points.size());
  f.rmse = std::sqrt(sum2 / n);
  f.std = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  return f;
}
}  // namespace

Fit plane_fit(const std::vector<vo::Vec3>& points) { return subspace_fit(points, 2); }
Fit line_fit(const std::vector<vo::Vec3>& points) { return subspace_fit(points, 1); }

}  // namespace bolo::odo
