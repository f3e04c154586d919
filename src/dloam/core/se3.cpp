#include "dloam/core/se3.hpp"

#include <cmath>

namespace dloam {

namespace {
// V matrix of the SE(3) exponential: t = V(omega) * v.
Eigen::Matrix3d left_jacobian(const Vec3& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = hat(w);
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * W;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}
}  // namespace

Pose exp_se3(const Vec6& xi) {
  const Vec3 w = xi.head<3>();
  const Vec3 v = xi.tail<3>();
  Pose T = Pose::Identity();
  const double theta = w.norm();
  T.linear() =
      theta < 1e-12 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
  T.translation() = left_jacobian(w) * v;
  return T;
}

Vec6 log_se3(const Pose& T) {
  const Eigen::AngleAxisd aa(T.rotation());
  const Vec3 w = aa.angle() * aa.axis();
  Vec6 xi;
  xi.head<3>() = w;
  xi.tail<3>() = left_jacobian(w).inverse() * T.translation();
  return xi;
}

}  // namespace dloam
