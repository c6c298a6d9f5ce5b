#include "bolo/odometry/tum.hpp"

#include <cstdio>
#include <fstream>
#include <string>

#include "bolo/sim/scene/pose.hpp"

namespace bolo::odo {

std::vector<StampedPose> read_tum(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open");
  std::vector<StampedPose> poses;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = file.string() + ": line " + std::to_string(number);
    sim::scene::StampedPose parsed;
    try {
      parsed = sim::scene::parse_tum_line(line);
    } catch (const std::invalid_argument& e) {
      throw Error(where + ": " + e.what());
    }
    if (!poses.empty() && parsed.t <= poses.back().t) throw Error(where + ": time t is not increasing");
    StampedPose p;
    p.t = parsed.t;
    p.T_wc.t = parsed.pose.position;
    p.T_wc.R = parsed.pose.orientation.toRotationMatrix();
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
