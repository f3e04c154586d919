#include "dloam/core/range_image.hpp"

#include <cmath>

namespace dloam {

int azimuth_column(double x, double y, int cols) {
  const int c = static_cast<int>(azimuth_time(x, y) * cols);
  return c >= cols ? cols - 1 : c;
}

double azimuth_time(double x, double y) {
  double t = (M_PI - std::atan2(y, x)) / (2.0 * M_PI);
  if (t >= 1.0) t -= 1.0;
  if (t < 0.0) t += 1.0;
  return t;
}

double point_elevation_deg(const Vec3& p) {
  return std::atan2(p.z(), std::hypot(p.x(), p.y())) * 180.0 / M_PI;
}

RangeImage project(const std::vector<Vec3>& points, const SensorConfig& sensor) {
  RangeImage img;
  img.rows = sensor.N_scan;
  img.cols = sensor.Horizon_SCAN;
  const auto n_pix = static_cast<std::size_t>(img.rows) * static_cast<std::size_t>(img.cols);
  img.range.assign(n_pix, 0.0f);
  img.point_of_pixel.assign(n_pix, -1);
  img.row_of_point.assign(points.size(), -1);
  img.col_of_point.assign(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const double r = p.norm();
    if (!(r >= sensor.min_range && r <= sensor.max_range)) continue;  // also rejects NaN
    const int row = sensor.row_of_elevation(point_elevation_deg(p));
    if (row < 0) continue;
    const int col = azimuth_column(p.x(), p.y(), img.cols);
    img.row_of_point[i] = row;
    img.col_of_point[i] = col;
    const auto px = static_cast<std::size_t>(img.pixel(row, col));
    if (img.point_of_pixel[px] < 0 || r < img.range[px]) {
      img.range[px] = static_cast<float>(r);
      img.point_of_pixel[px] = static_cast<int>(i);
    }
  }
  return img;
}

}  // namespace dloam
