#include "bolo/odometry/trajectory_plot.hpp"

#include <iterator>

#include "bolo/odometry/align.hpp"

namespace bolo::odo {

std::vector<PlotSeries> trajectory_series(const std::vector<StampedPose>& trajectory, const std::vector<std::size_t>& pose_segment,
                                          const std::optional<std::vector<StampedPose>>& truth, double period,
                                          const std::string& label) {
  static const char* const kSegmentColours[] = {"#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
  std::vector<PlotSeries> series;
  const bool segmented = !pose_segment.empty() && pose_segment.back() != pose_segment.front();
  // Numbered and coloured by segment (1 + the restarts before it), as `bolo evaluate` numbers them:
  // a segment too short to align is not drawn and leaves its number unused.
  const auto segment_series = [&](std::size_t segment) {
    return PlotSeries{label + ", segment " + std::to_string(segment + 1) + (truth ? " (aligned on its own)" : ""),
                      kSegmentColours[segment % std::size(kSegmentColours)], {}};
  };
  if (!truth) {
    if (!segmented) {
      series.push_back({label, kSegmentColours[0], {}});
      for (const StampedPose& p : trajectory) series.back().points.push_back(p.T_wc.t);
      return series;
    }
    for (std::size_t k = 0; k < trajectory.size(); ++k) {
      if (k == 0 || pose_segment[k] != pose_segment[k - 1]) series.push_back(segment_series(pose_segment[k]));
      series.back().points.push_back(trajectory[k].T_wc.t);
    }
    return series;
  }
  const Association a = associate(trajectory, *truth, 0.5 * (period > 0 ? period : 0.01));
  std::vector<vo::Vec3> from, to;
  std::vector<std::size_t> match_segment;
  for (std::size_t k = 0; k < a.estimate.size(); ++k) {
    from.push_back(trajectory[a.estimate[k]].T_wc.t), to.push_back((*truth)[a.truth[k]].T_wc.t);
    match_segment.push_back(pose_segment[a.estimate[k]]);
  }
  PlotSeries gt{"ground truth", "#1f77b4", {}};
  const double t_end = trajectory.empty() ? 0 : trajectory.back().t;
  for (const StampedPose& p : *truth)
    if (p.t <= t_end + 1e-9) gt.points.push_back(p.T_wc.t);
  series.push_back(gt);
  if (!segmented) {
    const Similarity sim = umeyama(from, to, true);
    series.push_back({label, kSegmentColours[0], {}});
    for (const StampedPose& p : trajectory) series.back().points.push_back(sim.apply(p.T_wc.t));
    return series;
  }
  for (const SegmentAlignment& fit : align_segments(from, to, match_segment)) {
    if (!fit.similarity) continue;  // under 3 poses: nothing to align it with
    const std::size_t segment = match_segment[fit.begin];
    PlotSeries s = segment_series(segment);
    for (std::size_t k = 0; k < trajectory.size(); ++k)
      if (pose_segment[k] == segment) s.points.push_back(fit.similarity->apply(trajectory[k].T_wc.t));
    series.push_back(s);
  }
  return series;
}

}  // namespace bolo::odo
