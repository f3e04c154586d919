// Range-image clustering (Bogoslavskyi & Stachniss) of the non-ground pixels.
#include "dloam/core/clustering.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace dloam {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kPending = -2;   // valid non-ground pixel not visited yet
constexpr int kInSearch = -3;  // reached by the current breadth-first search

// beta > theta for two neighbouring ranges seen `a` apart (sin_a, cos_a given).
struct JoinTest {
  double theta = 0.0, tan_theta = 0.0;
  [[nodiscard]] bool operator()(double r1, double r2, double sin_a, double cos_a) const {
    const double d1 = std::max(r1, r2), d2 = std::min(r1, r2);
    const double y = d2 * sin_a, x = d1 - d2 * cos_a;
    if (theta >= 0.5 * M_PI) return std::atan2(y, x) > theta;
    return x <= 0.0 || y > tan_theta * x;  // beta is in (0, pi): beta >= 90 deg > theta when x <= 0
  }
};

}  // namespace

ClusterResult cluster_range_image(const RangeImage& image, const std::vector<std::uint8_t>& ground_mask,
                                  const SensorConfig& sensor, const ClusteringConfig& config) {
  const int rows = image.rows, cols = image.cols;
  ClusterResult out;
  out.label.assign(image.range.size(), kOutlierLabel);
  for (std::size_t px = 0; px < out.label.size(); ++px) {
    if (image.point_of_pixel[px] < 0) continue;
    out.label[px] = (!ground_mask.empty() && ground_mask[px]) ? kGroundLabel : kPending;
  }
  const JoinTest join{config.segment_theta_deg * kDeg, std::tan(config.segment_theta_deg * kDeg)};
  const double a_h = 2.0 * M_PI / cols;
  const double sin_h = std::sin(a_h), cos_h = std::cos(a_h);
  const double sin_h2 = std::sin(2 * a_h), cos_h2 = std::cos(2 * a_h);
  std::vector<double> sin_v(static_cast<std::size_t>(rows), 0.0), cos_v(static_cast<std::size_t>(rows), 1.0);
  std::vector<double> sin_v2 = sin_v, cos_v2 = cos_v;
  for (int v = 0; v + 1 < rows; ++v) {  // angle between row v and v + 1 (v + 2)
    const double a = std::abs(sensor.beam_elevation_deg(v + 1) - sensor.beam_elevation_deg(v)) * kDeg;
    sin_v[static_cast<std::size_t>(v)] = std::sin(a);
    cos_v[static_cast<std::size_t>(v)] = std::cos(a);
    if (v + 2 >= rows) continue;
    const double a2 = std::abs(sensor.beam_elevation_deg(v + 2) - sensor.beam_elevation_deg(v)) * kDeg;
    sin_v2[static_cast<std::size_t>(v)] = std::sin(a2);
    cos_v2[static_cast<std::size_t>(v)] = std::cos(a2);
  }

  std::vector<std::pair<int, int>> queue;  // (row, column) of the pixels reached
  std::vector<char> row_seen(static_cast<std::size_t>(rows));
  for (int start = 0; start < rows * cols; ++start) {
    if (out.label[static_cast<std::size_t>(start)] != kPending) continue;
    queue.assign(1, {start / cols, start % cols});
    out.label[static_cast<std::size_t>(start)] = kInSearch;
    std::fill(row_seen.begin(), row_seen.end(), 0);
    int rows_spanned = 0;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const auto [v, u] = queue[head];
      if (!row_seen[static_cast<std::size_t>(v)]) row_seen[static_cast<std::size_t>(v)] = 1, ++rows_spanned;
      const double r = image.range[static_cast<std::size_t>(v * cols + u)];
      auto visit = [&](int nv, int nu, double s, double c) {
        const auto n = static_cast<std::size_t>(nv * cols + nu);
        if (out.label[n] != kPending || !join(r, image.range[n], s, c)) return;
        out.label[n] = kInSearch;
        queue.emplace_back(nv, nu);
      };
      const int left = u == 0 ? cols - 1 : u - 1, right = u == cols - 1 ? 0 : u + 1;
      visit(v, left, sin_h, cos_h);
      visit(v, right, sin_h, cos_h);
      // Bridge a single empty pixel in the row.
      if (image.point_at(v, left) < 0) visit(v, left == 0 ? cols - 1 : left - 1, sin_h2, cos_h2);
      if (image.point_at(v, right) < 0) visit(v, right == cols - 1 ? 0 : right + 1, sin_h2, cos_h2);
      if (v > 0)
        visit(v - 1, u, sin_v[static_cast<std::size_t>(v - 1)], cos_v[static_cast<std::size_t>(v - 1)]);
      if (v + 1 < rows)
        visit(v + 1, u, sin_v[static_cast<std::size_t>(v)], cos_v[static_cast<std::size_t>(v)]);
      if (v > 1 && image.point_at(v - 1, u) < 0)
        visit(v - 2, u, sin_v2[static_cast<std::size_t>(v - 2)], cos_v2[static_cast<std::size_t>(v - 2)]);
      if (v + 2 < rows && image.point_at(v + 1, u) < 0)
        visit(v + 2, u, sin_v2[static_cast<std::size_t>(v)], cos_v2[static_cast<std::size_t>(v)]);
    }
    const int size = static_cast<int>(queue.size());
    const bool keep = size >= config.N_min_cluster ||
                      (size >= config.N_min_cluster_small && rows_spanned >= config.N_min_cluster_rows);
    const int id = keep ? ++out.num_clusters : kOutlierLabel;
    for (const auto& [v, u] : queue) out.label[static_cast<std::size_t>(v * cols + u)] = id;
  }
  return out;
}

}  // namespace dloam
