#include "bolo/odometry/ply.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "bolo/odometry/tum.hpp"

namespace bolo::odo {

std::string ply_text(const std::vector<vo::WorldPoint>& points) {
  std::string s = "ply\nformat ascii 1.0\ncomment bolo odometry: keyframe points, world coordinates\n"
                  "element vertex " + std::to_string(points.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n";
  char buf[128];
  for (const vo::WorldPoint& p : points) {
    std::snprintf(buf, sizeof buf, "%.5f %.5f %.5f %.1f\n", static_cast<double>(p.x), static_cast<double>(p.y),
                  static_cast<double>(p.z), static_cast<double>(p.intensity));
    s += buf;
  }
  return s;
}

std::vector<vo::Vec3> read_ply_points(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open");
  std::string line;
  std::size_t count = 0;
  bool header_ok = false;
  while (std::getline(in, line)) {
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
    if (line == "format ascii 1.0") header_ok = true;
    if (line == "end_header") break;
  }
  if (!header_ok) throw Error(file.string() + ": not an ASCII ply");
  std::vector<vo::Vec3> points;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::getline(in, line)) throw Error(file.string() + ": vertex " + std::to_string(i) + " missing");
    std::istringstream f(line);
    double x, y, z;
    if (!(f >> x >> y >> z)) throw Error(file.string() + ": vertex " + std::to_string(i) + " is not x y z");
    points.emplace_back(x, y, z);
  }
  return points;
}

}  // namespace bolo::odo
