#include "dloam/drivers/ouster_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "dloam/drivers/huge_pages.hpp"

namespace dloam::drivers {

OusterXyzLut::OusterXyzLut(const OusterMetadata& md)
    : width_(md.columns_per_frame), height_(md.pixels_per_column) {
  constexpr double kDeg = M_PI / 180.0;
  const double n = md.beam_to_lidar(0, 3);
  const double bz = md.beam_to_lidar(2, 3);
  const double dist = bz != 0.0 ? std::hypot(n, bz) : n;
  const Eigen::Matrix3d R = md.lidar_to_sensor.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = md.lidar_to_sensor.topRightCorner<3, 1>();
  // The trigonometry of each row, each column and each distinct beam azimuth once (rows share
  // them: 16 of 128 on an OS-1-128, 111 on an OS-0-128); a pixel's direction from the sum formulas
  // cos(enc + az) = cos enc cos az - sin enc sin az, sin(enc + az) = sin enc cos az + cos enc sin az
  // (within 1e-15 of the sine and cosine of the sum, without a sine per pixel).
  const auto h = static_cast<std::size_t>(height_);
  std::vector<double> cos_alt(h), sin_alt(h), beam_az;
  std::vector<std::size_t> az_of_row(h);
  for (std::size_t row = 0; row < h; ++row) {
    const double az = -md.beam_azimuth_deg[row] * kDeg;
    const auto same = std::find(beam_az.begin(), beam_az.end(), az);
    az_of_row[row] = static_cast<std::size_t>(same - beam_az.begin());
    if (same == beam_az.end()) beam_az.push_back(az);
    const double alt = md.beam_altitude_deg[row] * kDeg;
    cos_alt[row] = std::cos(alt);
    sin_alt[row] = std::sin(alt);
  }
  std::vector<double> cos_az(beam_az.size()), sin_az(beam_az.size()), cos_sum(beam_az.size()),
      sin_sum(beam_az.size());  // of az and of enc + az
  for (std::size_t k = 0; k < beam_az.size(); ++k) {
    cos_az[k] = std::cos(beam_az[k]);
    sin_az[k] = std::sin(beam_az[k]);
  }
  // Written once, so not value-initialised first (std::vector would zero 6 MB for a 1024 x 128
  // sensor).
  const std::size_t entries = 6 * static_cast<std::size_t>(width_) * h;
  lut_.reset(new double[entries]);
  advise_huge_pages(lut_.get(), entries * sizeof(double));
  double* out = lut_.get();
  for (int m = 0; m < width_; ++m) {
    const double enc = 2.0 * M_PI - m * (2.0 * M_PI / width_);
    const double cos_enc = std::cos(enc), sin_enc = std::sin(enc);
    for (std::size_t k = 0; k < beam_az.size(); ++k) {
      cos_sum[k] = cos_enc * cos_az[k] - sin_enc * sin_az[k];
      sin_sum[k] = sin_enc * cos_az[k] + cos_enc * sin_az[k];
    }
    for (std::size_t row = 0; row < h; ++row, out += 6) {
      const std::size_t k = az_of_row[row];
      const Eigen::Vector3d d(cos_sum[k] * cos_alt[row], sin_sum[k] * cos_alt[row], sin_alt[row]);
      const Eigen::Vector3d o(cos_enc * n - d.x() * dist, sin_enc * n - d.y() * dist, -d.z() * dist + bz);
      const Eigen::Vector3d ds = R * d;
      const Eigen::Vector3d os = R * o + t;
      for (int c = 0; c < 3; ++c) {
        out[c] = ds[c] * 1e-3;
        out[3 + c] = os[c] * 1e-3;
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
  const double* e = entry(row, m);
  return Vec3(e[0], e[1], e[2]) * 1e3;
}

Vec3 OusterXyzLut::offset(int row, int m) const {
  const double* e = entry(row, m);
  return {e[3], e[4], e[5]};
}

}  // namespace dloam::drivers
