// Minimal SE(3) algebra over Eigen: exp/log maps, interpolation (paper eq. 12), small helpers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dloam/core/types.hpp"

namespace dloam {

using Vec6 = Eigen::Matrix<double, 6, 1>;  ///< twist [omega; v] (rotation first)
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Skew-symmetric matrix of w.
inline Eigen::Matrix3d hat(const Vec3& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

/// exp: twist -> rigid transform (exact SE(3) exponential).
Pose exp_se3(const Vec6& xi);
/// log: rigid transform -> twist.
Vec6 log_se3(const Pose& T);
/// The fraction s of the motion T (s in [0, 1] interpolates, paper eq. 12; any real s works).
inline Pose scale_motion(const Pose& T, double s) { return exp_se3(s * log_se3(T)); }
/// Rotation angle (rad) of T and its translation norm.
inline double rotation_angle(const Pose& T) { return Eigen::AngleAxisd(T.rotation()).angle(); }
inline double translation_norm(const Pose& T) { return T.translation().norm(); }
/// Re-orthonormalises the rotation part (after long products of poses).
inline Pose normalized(const Pose& T) {
  Pose out = T;
  out.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  return out;
}

}  // namespace dloam
