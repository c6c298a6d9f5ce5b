#pragma once
// Camera poses and the TUM trajectory line format.
//
// Conventions (used by the whole of bolo::sim::scene):
// - World frame: right-handed, z up, the ground is the plane z = 0, metres. The `street` scene
//   runs its main street along +x (x east, y north).
// - Camera frame: x right, y down, z forward (optical axis), as in the pinhole model.
// - A Pose is camera-to-world: p_world = orientation * p_camera + position (TUM convention).

#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bolo::sim::scene {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();                // camera centre in the world
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();   // camera-to-world rotation

  Eigen::Isometry3d isometry() const;                            // camera-to-world transform
  Eigen::Vector3d to_world(const Eigen::Vector3d& p_camera) const;
  Eigen::Vector3d to_camera(const Eigen::Vector3d& p_world) const;
};

// A camera pose from a vehicle-style attitude: yaw about world z (0 = looking along +x, positive
// = turning left, towards +y), pitch (positive = looking up), roll about the optical axis
// (positive = the image's right side goes down). Angles in radians.
Pose camera_pose(const Eigen::Vector3d& position, double yaw, double pitch, double roll = 0.0);

// A camera at `eye` looking at `target`, with the image's up direction as close to `up` as
// possible. Throws std::invalid_argument when target == eye or the view is parallel to `up`.
Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
             const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

// The rotation angle (radians, 0..pi) between two orientations, and the translation distance.
double rotation_angle(const Pose& a, const Pose& b);
double translation_distance(const Pose& a, const Pose& b);

// One TUM line `t tx ty tz qx qy qz qw` followed by '\n' (unit quaternion, qw >= 0).
std::string to_tum(double t, const Pose& pose);

struct StampedPose {
  double t = 0.0;
  Pose pose;
};
// Parses one TUM line (the quaternion is normalised): the one TUM parser of the project (bolo
// evaluate and the odometry tools read files through it). Throws std::invalid_argument saying
// what is wrong (not 8 numbers, a value not finite, a zero quaternion); callers add file and line.
StampedPose parse_tum_line(std::string_view line);

}  // namespace bolo::sim::scene
