#pragma once
// Top view (x, y) of trajectories as an SVG: the estimate (after alignment) and the ground truth.

#include <string>
#include <vector>

#include "bolo/vo/se3.hpp"

namespace bolo::odo {

struct PlotSeries {
  std::string label;
  std::string colour;  // SVG colour
  std::vector<vo::Vec3> points;
};

std::string trajectory_svg(const std::string& title, const std::vector<PlotSeries>& series);

}  // namespace bolo::odo
