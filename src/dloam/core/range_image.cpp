// Range-image projection (paper eqs. 4-6): rows from the sensor's beam table (BeamLookup, which
// also accounts for beam origin heights), columns from the azimuth in sweep order.
#include "dloam/core/range_image.hpp"

#include <algorithm>
#include <cmath>

namespace dloam {

int azimuth_column(double x, double y, int cols) {
  const int c = static_cast<int>(azimuth_time(x, y) * cols);
  return c >= cols ? cols - 1 : c;
}

double fast_atan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx <= 0.0) return 0.0;
  const double a = mn / mx, s = a * a;
  double r =
      a * (0.99997726 +
           s * (-0.33262347 + s * (0.19354346 + s * (-0.11643287 + s * (0.05265332 + s * -0.01172120)))));
  if (ay > ax) r = 0.5 * M_PI - r;
  if (x < 0.0) r = M_PI - r;
  return y < 0.0 ? -r : r;
}

double azimuth_time(double x, double y) {
  constexpr double kInvTwoPi = 0.5 / M_PI;  // a product: this runs for every point of every projection
  double t = (M_PI - fast_atan2(y, x)) * kInvTwoPi;
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
  const BeamLookup lookup(sensor);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const double r = p.norm();
    if (!(r >= sensor.min_range && r <= sensor.max_range)) continue;  // also rejects NaN
    const int row = lookup.row(p);
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

std::vector<float> reprojected_range(const RangeImage& image, const std::vector<Vec3>& points,
                                     const std::vector<std::uint8_t>& excluded) {
  std::vector<float> range(image.range.size(), 0.0f);
  for (std::size_t i = 0; i < points.size() && i < image.row_of_point.size(); ++i) {
    const int px = image.pixel_of_point(i);
    if (px < 0 || (!excluded.empty() && excluded[static_cast<std::size_t>(px)])) continue;
    const Vec3& p = points[i];
    const auto r = static_cast<float>(p.norm());
    float& slot = range[static_cast<std::size_t>(
        image.pixel(image.row_of_point[i], azimuth_column(p.x(), p.y(), image.cols)))];
    if (slot == 0.0f || r < slot) slot = r;
  }
  return range;
}

}  // namespace dloam
