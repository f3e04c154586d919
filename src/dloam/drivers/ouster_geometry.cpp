#include "dloam/drivers/ouster_geometry.hpp"

#include <cmath>

namespace dloam::drivers {

OusterXyzLut::OusterXyzLut(const OusterMetadata& md)
    : width_(md.columns_per_frame), height_(md.pixels_per_column) {
  constexpr double kDeg = M_PI / 180.0;
  const double n = md.beam_to_lidar(0, 3);
  const double bz = md.beam_to_lidar(2, 3);
  const double dist = bz != 0.0 ? std::hypot(n, bz) : n;
  const Eigen::Matrix3d R = md.lidar_to_sensor.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = md.lidar_to_sensor.topRightCorner<3, 1>();
  const auto size = 3 * static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  dir_.resize(size);
  off_.resize(size);
  for (int m = 0; m < width_; ++m) {
    const double enc = 2.0 * M_PI - m * (2.0 * M_PI / width_);
    for (int row = 0; row < height_; ++row) {
      const double az = -md.beam_azimuth_deg[static_cast<std::size_t>(row)] * kDeg;
      const double alt = md.beam_altitude_deg[static_cast<std::size_t>(row)] * kDeg;
      const Eigen::Vector3d d(std::cos(enc + az) * std::cos(alt), std::sin(enc + az) * std::cos(alt),
                              std::sin(alt));
      const Eigen::Vector3d o(std::cos(enc) * n - d.x() * dist, std::sin(enc) * n - d.y() * dist,
                              -d.z() * dist + bz);
      const Eigen::Vector3d ds = R * d;
      const Eigen::Vector3d os = R * o + t;
      const std::size_t i = 3 * (static_cast<std::size_t>(m) * static_cast<std::size_t>(height_) +
                                 static_cast<std::size_t>(row));
      for (int k = 0; k < 3; ++k) {
        dir_[i + static_cast<std::size_t>(k)] = ds[k] * 1e-3;
        off_[i + static_cast<std::size_t>(k)] = os[k] * 1e-3;
      }
    }
  }
  // The beam origins lie on a circle of radius n about the lidar axis at height b_z; the
  // sensor frame's z of that circle's centre.
  origin_height_ = (R * Eigen::Vector3d(0.0, 0.0, bz) + t).z() * 1e-3;
  row_heights_.resize(static_cast<std::size_t>(height_));
  for (int row = 0; row < height_; ++row) {
    const double az = md.beam_azimuth_deg[static_cast<std::size_t>(row)] * kDeg;
    const double alt = md.beam_altitude_deg[static_cast<std::size_t>(row)] * kDeg;
    row_heights_[static_cast<std::size_t>(row)] = origin_height_ - n * 1e-3 * std::cos(az) * std::tan(alt);
  }
}

Vec3 OusterXyzLut::direction(int row, int m) const {
  const std::size_t i =
      3 * (static_cast<std::size_t>(m) * static_cast<std::size_t>(height_) + static_cast<std::size_t>(row));
  return Vec3(dir_[i], dir_[i + 1], dir_[i + 2]) * 1e3;
}

Vec3 OusterXyzLut::offset(int row, int m) const {
  const std::size_t i =
      3 * (static_cast<std::size_t>(m) * static_cast<std::size_t>(height_) + static_cast<std::size_t>(row));
  return {off_[i], off_[i + 1], off_[i + 2]};
}

}  // namespace dloam::drivers
