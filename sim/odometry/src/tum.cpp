#include "bolo/odometry/tum.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace bolo::odo {

std::vector<StampedPose> read_tum(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open");
  std::vector<StampedPose> poses;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    int n = 0;
    while (n < 8 && fields >> v[n]) ++n;
    std::string extra;
    const std::string where = file.string() + ": line " + std::to_string(number);
    if (n != 8 || (fields >> extra)) throw Error(where + ": expected 8 numbers (t tx ty tz qx qy qz qw)");
    for (double x : v)
      if (!std::isfinite(x)) throw Error(where + ": a value is not finite");
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (qn < 1e-6) throw Error(where + ": quaternion has zero length");
    if (!poses.empty() && v[0] <= poses.back().t) throw Error(where + ": time t is not increasing");
    StampedPose p;
    p.t = v[0];
    p.T_wc.t = vo::Vec3(v[1], v[2], v[3]);
    p.T_wc.R = vo::from_quaternion(v[4], v[5], v[6], v[7]);
    poses.push_back(p);
  }
  return poses;
}

std::string tum_line(const StampedPose& pose) {
  const Eigen::Vector4d q = vo::to_quaternion(pose.T_wc.R);
  // Fixed nine decimals (the TUM tools' convention) can take over 300 characters for a large
  // coordinate: ask snprintf for the length instead of cutting the line short.
  const auto print = [&](char* out, std::size_t size) {
    return std::snprintf(out, size, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", pose.t,
                         pose.T_wc.t.x(), pose.T_wc.t.y(), pose.T_wc.t.z(), q.x(), q.y(), q.z(),
                         q.w());
  };
  std::string line(static_cast<std::size_t>(print(nullptr, 0)), '\0');
  print(line.data(), line.size() + 1);
  return line;
}

}  // namespace bolo::odo
