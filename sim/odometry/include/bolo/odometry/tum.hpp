#pragma once
// TUM trajectories (`t tx ty tz qx qy qz qw`, camera-to-world) for the VO's output and the
// simulator's ground truth.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "bolo/vo/se3.hpp"

namespace bolo::odo {

// Bad input to the odometry tools; the message names the file, line or field.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StampedPose {
  double t = 0;
  vo::Se3 T_wc;  // camera-to-world
};

// Throws Error naming the file and line for anything but 8 finite numbers per line ('#' lines
// and blank lines are skipped), a non-unit-able quaternion, or time not increasing.
std::vector<StampedPose> read_tum(const std::filesystem::path& file);
std::string tum_line(const StampedPose& pose);

}  // namespace bolo::odo
