#pragma once
// ASCII .ply point clouds (x y z as float, intensity as float) for the VO's map points.

#include <filesystem>
#include <string>
#include <vector>

#include "bolo/vo/odometry.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::odo {

std::string ply_text(const std::vector<vo::WorldPoint>& points);
// Reads the x, y, z of an ASCII ply written by ply_text (Error naming the file otherwise).
std::vector<vo::Vec3> read_ply_points(const std::filesystem::path& file);

}  // namespace bolo::odo
