// Range-image projection (paper eq. 4-6) keeping the point <-> pixel correspondence both ways.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// Row v counts beams from the bottom (row 0 = Pit_bottom, eq. 4; the beam table of the sensor
/// when it has one, searched from each beam's origin height: SensorConfig::row_of_point). Column u counts the
/// azimuth clockwise seen from above starting at the rear (-x) of the sensor, which is also
/// the sweep order of a Velodyne/Ouster: u / Horizon_SCAN is the point's time in the sweep.
struct RangeImage {
  int rows = 0;
  int cols = 0;
  std::vector<float> range;         ///< rows*cols, 0 where no point
  std::vector<int> point_of_pixel;  ///< rows*cols, index of the (nearest) point, -1 where none
  std::vector<int> row_of_point;    ///< per input point, -1 when outside FOV / range limits
  std::vector<int> col_of_point;    ///< per input point, -1 when outside FOV / range limits

  [[nodiscard]] int pixel(int row, int col) const { return row * cols + col; }
  [[nodiscard]] float at(int row, int col) const { return range[static_cast<std::size_t>(pixel(row, col))]; }
  [[nodiscard]] int point_at(int row, int col) const {
    return point_of_pixel[static_cast<std::size_t>(pixel(row, col))];
  }
  /// Pixel of input point i, or -1.
  [[nodiscard]] int pixel_of_point(std::size_t i) const {
    return row_of_point[i] < 0 ? -1 : pixel(row_of_point[i], col_of_point[i]);
  }
};

/// Column of a direction (paper eq. 5, with the sweep-order convention above).
int azimuth_column(double x, double y, int cols);
/// atan2 by a minimax polynomial of atan on [0, 1]: max error 1.7e-6 rad (a column of a
/// 2048-column image is 3e-3 rad), exact on the axes, several times cheaper than std::atan2.
double fast_atan2(double y, double x);
/// Time in [0, 1) of the sweep for a point at (x, y), from its azimuth (rear start, clockwise).
double azimuth_time(double x, double y);
/// Elevation (deg) of a point above the sensor's horizontal plane.
double point_elevation_deg(const Vec3& p);

/// Projects points into a range image. Several points in one pixel: the nearest wins, the
/// others keep their row/col (so labels can be back-projected to every point). Points outside
/// the vertical field of view or the range limits get row/col -1.
RangeImage project(const std::vector<Vec3>& points, const SensorConfig& sensor);

/// The ranges of image's points after they moved a little (a second de-skew): each point keeps its
/// row, its column follows its new azimuth, the nearest point of a pixel wins. Points that image
/// left out stay out, and so do those whose pixel in image is set in excluded (when not empty).
std::vector<float> reprojected_range(const RangeImage& image, const std::vector<Vec3>& points,
                                     const std::vector<std::uint8_t>& excluded);

}  // namespace dloam
