// Poses for tests: a yaw (and roll / pitch) and a translation.
#pragma once

#include <Eigen/Geometry>

#include "dloam/core/se3.hpp"

namespace dloam::test {

/// Rotation yaw * pitch * roll (about z, y, x) and translation `t`.
inline Pose make_pose(double roll, double pitch, double yaw, const Vec3& t) {
  Pose T = Pose::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                Eigen::AngleAxisd(roll, Vec3::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

/// A turn about z by `yaw` and translation `t`.
inline Pose make_pose(double yaw, const Vec3& t) { return make_pose(0.0, 0.0, yaw, t); }

}  // namespace dloam::test
