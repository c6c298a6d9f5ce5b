#pragma once
// A smooth planar path (x, y, heading) made of straight runs and turns. A turn changes the
// heading by `turn` radians over `length` metres with a smooth trapezoidal curvature profile
// (curvature ramps in and out as smoothsteps), so position, heading and curvature are all
// continuous. Positions come from a fine table integrated with Simpson's rule and cubic Hermite
// interpolation (error far below a micrometre).

#include <vector>

#include <Eigen/Core>

namespace bolo::sim::scene::detail {

class PlanarPath {
 public:
  struct Segment {
    double length;
    double turn = 0.0;  // radians, positive = left (counter-clockwise seen from +z)
  };
  struct State {
    Eigen::Vector2d p;
    double heading;
  };

  PlanarPath(const Eigen::Vector2d& start, double heading, std::vector<Segment> segments);

  double length() const { return length_; }
  // Beyond [0, length()] the path continues straight.
  State at(double s) const;
  double heading_at(double s) const;
  double curvature_at(double s) const;

 private:
  Eigen::Vector2d start_;
  double heading0_;
  std::vector<Segment> segments_;
  std::vector<double> seg_start_;    // arc length at each segment's start
  std::vector<double> seg_heading_;  // heading at each segment's start
  double length_ = 0.0;
  double ds_ = 0.1;
  std::vector<Eigen::Vector2d> table_;
};

// Lateral/forward advance of a single turn (start at the origin heading +x).
Eigen::Vector2d turn_displacement(double length, double turn);

}  // namespace bolo::sim::scene::detail
