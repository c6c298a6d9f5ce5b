#pragma once
// What `bolo odometry` plots in trajectory.svg: the ground truth when there is one and the
// estimate aligned onto it (Sim(3)); a run that restarted drawn segment by segment.

#include <optional>
#include <string>
#include <vector>

#include "bolo/odometry/plot.hpp"
#include "bolo/odometry/tum.hpp"

namespace bolo::odo {

// pose_segment: each pose's tracking segment (tracking_segments(), align.hpp). A run that
// restarted is a chain of maps with their own scales and origins: each segment is then its own
// series (aligned on its own when there is a truth), not joined to the next by a jump. `period`:
// the frame interval, for matching poses with the truth in time.
std::vector<PlotSeries> trajectory_series(const std::vector<StampedPose>& trajectory,
                                          const std::vector<std::size_t>& pose_segment,
                                          const std::optional<std::vector<StampedPose>>& truth, double period,
                                          const std::string& label);

}  // namespace bolo::odo
