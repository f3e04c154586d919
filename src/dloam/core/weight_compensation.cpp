#include "dloam/core/weight_compensation.hpp"

#include <algorithm>
#include <limits>

namespace dloam {

std::vector<int> dynamic_column_distance(const std::vector<std::uint8_t>& pixel_dynamic, int rows, int cols) {
  std::vector<int> dist(static_cast<std::size_t>(cols), -1);
  if (pixel_dynamic.empty() || cols <= 0) return dist;
  std::vector<std::uint8_t> col_dyn(static_cast<std::size_t>(cols), 0);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u)
      if (pixel_dynamic[static_cast<std::size_t>(v * cols + u)]) col_dyn[static_cast<std::size_t>(u)] = 1;
  if (std::find(col_dyn.begin(), col_dyn.end(), 1) == col_dyn.end()) return dist;
  // Two sweeps around the circle in each direction (1-D distance transform with wrap-around).
  constexpr int kFar = std::numeric_limits<int>::max() / 4;
  std::vector<int> d(static_cast<std::size_t>(cols), kFar);
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < cols; ++k) {
      const auto u = static_cast<std::size_t>(k), prev = static_cast<std::size_t>((k + cols - 1) % cols);
      d[u] = col_dyn[u] ? 0 : std::min(d[u], d[prev] + 1);
    }
    for (int k = cols - 1; k >= 0; --k) {
      const auto u = static_cast<std::size_t>(k), next = static_cast<std::size_t>((k + 1) % cols);
      d[u] = col_dyn[u] ? 0 : std::min(d[u], d[next] + 1);
    }
  }
  return d;
}

double compensation_factor(int column_distance) {
  if (column_distance < 0) return 1.0;
  if (column_distance <= 1) return 0.0;
  return 1.0 - 1.0 / column_distance;
}

std::vector<double> compensated_weights(const std::vector<int>& feature_points, const RangeImage& image,
                                        const std::vector<int>& column_distance) {
  std::vector<double> w(feature_points.size(), 1.0);
  for (std::size_t k = 0; k < feature_points.size(); ++k) {
    const int col = image.col_of_point[static_cast<std::size_t>(feature_points[k])];
    if (col >= 0 && static_cast<std::size_t>(col) < column_distance.size())
      w[k] = compensation_factor(column_distance[static_cast<std::size_t>(col)]);
  }
  return w;
}

}  // namespace dloam
