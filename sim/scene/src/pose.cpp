#include "bolo/sim/scene/pose.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace bolo::sim::scene {

Eigen::Isometry3d Pose::isometry() const {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = orientation.normalized().toRotationMatrix();
  m.translation() = position;
  return m;
}

Eigen::Vector3d Pose::to_world(const Eigen::Vector3d& p_camera) const {
  return orientation.normalized() * p_camera + position;
}

Eigen::Vector3d Pose::to_camera(const Eigen::Vector3d& p_world) const {
  return orientation.normalized().conjugate() * (p_world - position);
}

Pose camera_pose(const Eigen::Vector3d& position, double yaw, double pitch, double roll) {
  // Body frame: x forward, y left, z up. Camera frame: x right, y down, z forward.
  Eigen::Matrix3d body_from_camera;
  body_from_camera << 0, 0, 1,
                     -1, 0, 0,
                      0, -1, 0;
  const Eigen::Matrix3d world_from_body =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  Pose p;
  p.position = position;
  p.orientation = Eigen::Quaterniond(world_from_body * body_from_camera).normalized();
  return p;
}

Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d d = target - eye;
  if (!(d.norm() > 0.0)) throw std::invalid_argument("look_at: target equals eye");
  const Eigen::Vector3d f = d.normalized();
  const Eigen::Vector3d r_raw = f.cross(up);
  if (!(r_raw.norm() > 1e-9 * up.norm()))
    throw std::invalid_argument("look_at: view direction parallel to the up vector");
  const Eigen::Vector3d r = r_raw.normalized();
  const Eigen::Vector3d down = f.cross(r);
  Eigen::Matrix3d m;
  m.col(0) = r;
  m.col(1) = down;
  m.col(2) = f;
  Pose p;
  p.position = eye;
  p.orientation = Eigen::Quaterniond(m).normalized();
  return p;
}

double rotation_angle(const Pose& a, const Pose& b) {
  return a.orientation.normalized().angularDistance(b.orientation.normalized());
}

double translation_distance(const Pose& a, const Pose& b) {
  return (a.position - b.position).norm();
}

std::string to_tum(double t, const Pose& pose) {
  Eigen::Quaterniond q = pose.orientation.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t,
                pose.position.x(), pose.position.y(), pose.position.z(), q.x(), q.y(), q.z(),
                q.w());
  return buf;
}

StampedPose parse_tum_line(std::string_view line) {
  const std::string s(line);
  constexpr const char* kShape = "expected 8 numbers (t tx ty tz qx qy qz qw)";
  double v[8];
  const char* p = s.c_str();
  for (double& x : v) {
    char* end = nullptr;
    x = std::strtod(p, &end);
    if (end == p) throw std::invalid_argument(kShape);
    p = end;
  }
  while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') ++p;
  if (*p != '\0') throw std::invalid_argument(kShape);
  for (double x : v)
    if (!std::isfinite(x)) throw std::invalid_argument("a value is not finite");
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
  if (!(q.norm() >= 1e-6)) throw std::invalid_argument("quaternion has zero length");
  StampedPose out;
  out.t = v[0];
  out.pose.position = Eigen::Vector3d(v[1], v[2], v[3]);
  out.pose.orientation = q.normalized();
  return out;
}

}  // namespace bolo::sim::scene
