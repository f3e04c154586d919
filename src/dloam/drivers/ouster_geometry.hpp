// Ouster range -> XYZ, the model published with the sensor documentation and ouster-sdk
// (make_xyz_lut): for measurement m of W and beam i,
//   encoder angle  th_e = 2 pi (1 - m / W),  azimuth th_a = -beam_azimuth_i,  altitude phi = beam_altitude_i
//   direction d = (cos(th_e + th_a) cos phi, sin(th_e + th_a) cos phi, sin phi)
//   offset    o = (n cos th_e, n sin th_e, b_z) - |b| d,   n = beam_to_lidar x (the beam origin
//               offset), b_z = beam_to_lidar z, |b| = sqrt(n^2 + b_z^2)
//   lidar-frame point = r d + o (mm), sensor-frame point = lidar_to_sensor * that.
// The lidar frame has x at encoder angle 0, the connector, i.e. pointing backwards; the
// lidar_to_sensor_transform of every sensor turns it by 180 deg about z (diag -1, -1, 1) and lifts
// it to the sensor's base, so the sensor frame has x forward, y left, z up (REP 103).
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/drivers/ouster_metadata.hpp"

namespace dloam::drivers {

class OusterXyzLut {
 public:
  explicit OusterXyzLut(const OusterMetadata& metadata);

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  /// Sensor-frame point (m) of pixel `row` (Ouster's beam order, top first) of measurement `m`
  /// for a range in mm (> 0).
  [[nodiscard]] Vec3 point(int row, int m, double range_mm) const {
    const double* e = entry(row, m);
    return {e[0] * range_mm + e[3], e[1] * range_mm + e[4], e[2] * range_mm + e[5]};
  }
  /// Unit direction and offset (m) of a pixel in the sensor frame: point = range_m * d + o.
  [[nodiscard]] Vec3 direction(int row, int m) const;
  [[nodiscard]] Vec3 offset(int row, int m) const;
  /// Height (m) of the lidar's optical mid-plane above the sensor frame's origin at the sensor's
  /// base: lidar_to_sensor z + beam_to_lidar z.
  [[nodiscard]] double beam_origin_height() const { return origin_height_; }
  /// Per row (Ouster's order): the height (m) on the sensor's axis from which the row's beam
  /// cone would be seen. A beam leaves from a point n off the axis (beam_to_lidar x), so its
  /// points lie on z = h_row + rho tan(phi), rho the distance from the axis, with
  /// h_row = mid-plane height - n cos(beam azimuth) tan(phi) (exact for far points).
  [[nodiscard]] const std::vector<double>& row_origin_heights() const { return row_heights_; }

 private:
  [[nodiscard]] const double* entry(int row, int m) const {
    return lut_.get() + 6 * (static_cast<std::size_t>(m) * static_cast<std::size_t>(height_) +
                             static_cast<std::size_t>(row));
  }

  int width_, height_;
  /// Per (m, row): the direction in m per mm of range, then the offset in m.
  std::unique_ptr<double[]> lut_;
  double origin_height_ = 0.0;
  std::vector<double> row_heights_;
};

}  // namespace dloam::drivers
