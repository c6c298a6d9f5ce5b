#pragma once
// Rigid motions for the VO: rotation matrix + translation, with the exponential and logarithm
// maps of SE(3). Tangent vectors are (translation; rotation), perturbations act on the left.

#include <Eigen/Core>

namespace bolo::vo {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct Se3 {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();

  Vec3 operator*(const Vec3& p) const { return R * p + t; }
  Se3 operator*(const Se3& o) const { return {R * o.R, R * o.t + t}; }
  Se3 inverse() const { return {R.transpose(), -(R.transpose() * t)}; }

  static Se3 exp(const Vec6& xi);
  Vec6 log() const;
  // The nearest rigid motion: R projected back onto the rotations. Rounding leaves R slightly
  // off; a pose composed with its own predecessor's inverse (the motion model) doubles that every
  // frame unless it is removed.
  Se3 orthonormalised() const;
};

Mat3 skew(const Vec3& v);
Mat3 so3_exp(const Vec3& w);
Vec3 so3_log(const Mat3& R);
// Unit quaternion (x, y, z, w) with w >= 0.
Eigen::Vector4d to_quaternion(const Mat3& R);
Mat3 from_quaternion(double x, double y, double z, double w);

}  // namespace bolo::vo
