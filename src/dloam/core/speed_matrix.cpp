#include "dloam/core/speed_matrix.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace dloam {

namespace {

/// Distance of r to the range interval of the valid pixels among (rows r0,r1) x (cols c0,c1).
float bracket_distance(const std::vector<float>& prev, int cols, int r0, int r1, int c0, int c1, float r) {
  float lo = 0.0f, hi = -1.0f;
  for (int v : {r0, r1})
    for (int u : {c0, c1}) {
      const float rp = prev[static_cast<std::size_t>(v * cols + u)];
      if (rp <= 0.0f) continue;
      if (hi < 0.0f) {
        lo = hi = rp;
      } else {
        lo = std::min(lo, rp);
        hi = std::max(hi, rp);
      }
    }
  if (hi < 0.0f) return -1.0f;
  return r < lo ? lo - r : (r > hi ? r - hi : 0.0f);
}

}  // namespace

SpeedMatrix compute_speed_matrix(const RangeImage& current, const std::vector<Vec3>& current_points,
                                 const Pose& current_to_previous, const std::vector<float>& previous,
                                 const SensorConfig& sensor) {
  const int rows = sensor.N_scan, cols = sensor.Horizon_SCAN;
  const auto n_pix = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  if (current.range.size() != n_pix || previous.size() != n_pix)
    throw InputError("compute_speed_matrix: range images of " + std::to_string(current.range.size()) + " / " +
                     std::to_string(previous.size()) + " pixels, the sensor has " + std::to_string(n_pix));
  SpeedMatrix S;
  S.rows = rows;
  S.cols = cols;
  S.speed.assign(n_pix, -1.0f);
  S.previous_pixel.assign(n_pix, -1);
  tbb::parallel_for(0, rows, [&](int v) {
    for (int u = 0; u < cols; ++u) {
      const int px = v * cols + u;
      const int i = current.point_of_pixel[static_cast<std::size_t>(px)];
      if (i < 0) continue;
      const Vec3 q = current_to_previous * current_points[static_cast<std::size_t>(i)];
      const double e = point_elevation_deg(q);
      const int row = sensor.row_of_elevation(e);
      if (row < 0) continue;
      const double t = azimuth_time(q.x(), q.y()) * cols;
      const int col = std::min(static_cast<int>(t), cols - 1);
      S.previous_pixel[static_cast<std::size_t>(px)] = row * cols + col;
      // The bracketing rows and columns (pixel centres at row elevations and col + 0.5).
      const int row2 = std::clamp(e > sensor.beam_elevation_deg(row) ? row + 1 : row - 1, 0, rows - 1);
      const int col2 = ((t - col >= 0.5 ? col + 1 : col - 1) + cols) % cols;
      S.speed[static_cast<std::size_t>(px)] =
          bracket_distance(previous, cols, row, row2, col, col2, static_cast<float>(q.norm()));
    }
  });
  return S;
}

}  // namespace dloam
