#include "bolo/vo/se3.hpp"

#include <cmath>

#include <Eigen/LU>

namespace bolo::vo {

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Mat3 so3_exp(const Vec3& w) {
  const double theta = w.norm();
  const Mat3 W = skew(w);
  if (theta < 1e-9) return Mat3::Identity() + W;
  return Mat3::Identity() + std::sin(theta) / theta * W +
         (1 - std::cos(theta)) / (theta * theta) * W * W;
}

Vec3 so3_log(const Mat3& R) {
  const double c = std::max(-1.0, std::min(1.0, 0.5 * (R.trace() - 1)));
  const double theta = std::acos(c);
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  if (theta < 1e-7) return 0.5 * v;
  if (M_PI - theta < 1e-6) {
    // Near pi the antisymmetric part vanishes: take the axis from the symmetric part.
    const Mat3 B = 0.5 * (R + Mat3::Identity());
    Vec3 axis(std::sqrt(std::max(0.0, B(0, 0))), std::sqrt(std::max(0.0, B(1, 1))),
              std::sqrt(std::max(0.0, B(2, 2))));
    if (B(0, 1) < 0) axis.y() = -axis.y();
    if (B(0, 2) < 0) axis.z() = -axis.z();
    return theta * axis.normalized();
  }
  return theta / (2 * std::sin(theta)) * v;
}

// V = I + (1-cos)/th^2 W + (th - sin)/th^3 W^2 couples rotation into the translation part.
static Mat3 left_jacobian(const Vec3& w) {
  const double theta = w.norm();
  const Mat3 W = skew(w);
  if (theta < 1e-9) return Mat3::Identity() + 0.5 * W;
  return Mat3::Identity() + (1 - std::cos(theta)) / (theta * theta) * W +
         (theta - std::sin(theta)) / (theta * theta * theta) * W * W;
}

Se3 Se3::exp(const Vec6& xi) {
  const Vec3 w = xi.tail<3>();
  return {so3_exp(w), left_jacobian(w) * xi.head<3>()};
}

Vec6 Se3::log() const {
  const Vec3 w = so3_log(R);
  Vec6 xi;
  xi.head<3>() = left_jacobian(w).inverse() * t;
  xi.tail<3>() = w;
  return xi;
}

Se3 Se3::orthonormalised() const {
  const Eigen::Vector4d q = to_quaternion(R);
  return {from_quaternion(q.x(), q.y(), q.z(), q.w()), t};
}

Eigen::Vector4d to_quaternion(const Mat3& R) {
  double x, y, z, w;
  const double tr = R.trace();
  if (tr > 0) {
    const double s = 2 * std::sqrt(tr + 1);
    w = s / 4, x = (R(2, 1) - R(1, 2)) / s, y = (R(0, 2) - R(2, 0)) / s, z = (R(1, 0) - R(0, 1)) / s;
  } else if (R(0, 0) > R(1, 1) && R(0, 0) > R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(0, 0) - R(1, 1) - R(2, 2));
    w = (R(2, 1) - R(1, 2)) / s, x = s / 4, y = (R(0, 1) + R(1, 0)) / s, z = (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) > R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(1, 1) - R(0, 0) - R(2, 2));
    w = (R(0, 2) - R(2, 0)) / s, x = (R(0, 1) + R(1, 0)) / s, y = s / 4, z = (R(1, 2) + R(2, 1)) / s;
  } else {
    const double s = 2 * std::sqrt(1 + R(2, 2) - R(0, 0) - R(1, 1));
    w = (R(1, 0) - R(0, 1)) / s, x = (R(0, 2) + R(2, 0)) / s, y = (R(1, 2) + R(2, 1)) / s, z = s / 4;
  }
  Eigen::Vector4d q(x, y, z, w);
  q.normalize();
  if (q.w() < 0) q = -q;
  return q;
}

Mat3 from_quaternion(double x, double y, double z, double w) {
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  x /= n, y /= n, z /= n, w /= n;
  Mat3 R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
       2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
       2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y);
  return R;
}

}  // namespace bolo::vo
