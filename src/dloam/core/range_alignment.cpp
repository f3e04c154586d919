#include "dloam/core/range_alignment.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>  // parallel_deterministic_reduce

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "dloam/core/range_image.hpp"
#include "dloam/core/se3.hpp"

namespace dloam {

namespace {

using Vec3f = Eigen::Vector3f;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Tangent at `c` from neighbours `a` (before) and `b` (after): central when both lie on c's
/// surface (closer than `reach`), one-sided when one does, zero when none.
Vec3f tangent(const Vec3f& a, const Vec3f& c, const Vec3f& b, float reach) {
  const bool ok_a = !a.isZero() && (c - a).norm() < reach;
  const bool ok_b = !b.isZero() && (b - c).norm() < reach;
  if (ok_a && ok_b) return b - a;
  if (ok_b) return b - c;
  if (ok_a) return c - a;
  return Vec3f::Zero();
}

struct NormalEquations {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  int pairs = 0;
  void add(const NormalEquations& o) {
    H += o.H;
    g += o.g;
    pairs += o.pairs;
  }
};

}  // namespace

void fill_vertex_map(const std::vector<Vec3>& points, const std::vector<int>& pixel_of_point, int rows,
                     int cols, VertexMap& map) {
  map.rows = rows;
  map.cols = cols;
  const std::size_t n_pix = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  // The nearest point per pixel: the smallest (range bits, point index) key. A positive float's
  // bits order like the float; the index breaks ties.
  constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t>& best = map.nearest_key;
  best.assign(n_pix, kEmpty);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int px = pixel_of_point[i];
    if (px < 0) continue;
    const auto r = static_cast<float>(points[i].norm());
    std::uint32_t bits = 0;
    std::memcpy(&bits, &r, sizeof bits);
    std::uint64_t& slot = best[static_cast<std::size_t>(px)];
    slot = std::min(slot, (std::uint64_t{bits} << 32) | static_cast<std::uint32_t>(i));
  }
  map.point.resize(n_pix);
  map.range.resize(n_pix);
  for (std::size_t px = 0; px < n_pix; ++px) {
    if (best[px] == kEmpty) {
      map.point[px] = Vec3f::Zero();
      map.range[px] = 0.0f;
      continue;
    }
    const auto bits = static_cast<std::uint32_t>(best[px] >> 32);
    std::memcpy(&map.range[px], &bits, sizeof bits);
    map.point[px] = points[static_cast<std::size_t>(best[px] & 0xFFFFFFFFu)].cast<float>();
  }
}

VertexMap make_vertex_map(const std::vector<Vec3>& points, const std::vector<int>& pixel_of_point, int rows,
                          int cols) {
  VertexMap map;
  fill_vertex_map(points, pixel_of_point, rows, cols, map);
  return map;
}

Eigen::Vector3f surface_normal(const VertexMap& map, int v, int u) {
  const int rows = map.rows, cols = map.cols;
  const auto at = [&](int vv, int uu) -> const Vec3f& {
    return map.point[static_cast<std::size_t>(vv * cols + (uu + cols) % cols)];
  };
  const Vec3f none = Vec3f::Zero();
  const Vec3f& c = at(v, u);
  if (c.isZero()) return none;
  const float r = c.norm();
  // Along a row neighbours are a fraction of a degree apart, across rows up to a few degrees (and
  // far apart on the ground): wider reach across.
  const Vec3f h = tangent(at(v, u - 1), c, at(v, u + 1), 0.05f * r + 0.2f);
  const Vec3f w = tangent(v > 0 ? at(v - 1, u) : none, c, v + 1 < rows ? at(v + 1, u) : none, 0.5f * r);
  Vec3f n = h.cross(w);
  const float len = n.norm();
  if (!(len > 1e-9f)) return none;
  n /= len;
  return n.dot(c) > 0.0f ? Vec3f(-n) : n;
}

AlignmentResult align_range_images(const std::vector<Vec3>& points, const std::vector<int>& point_of_pixel,
                                   const VertexMap& previous, const SensorConfig& sensor, const Pose& initial,
                                   const AlignmentOptions& options) {
  AlignmentResult result;
  result.T = initial;
  if (previous.empty()) return result;
  // About max_points samples: every step-th pixel, the step from the share of pixels with a point
  // (counted on a sparse subset of the image).
  std::vector<Vec3> samples;
  {
    std::size_t seen = 0, valid = 0;
    for (std::size_t px = 0; px < point_of_pixel.size(); px += 17, ++seen) valid += point_of_pixel[px] >= 0;
    const double filled = seen > 0 ? static_cast<double>(valid) / static_cast<double>(seen) : 0.0;
    const auto step = std::max<std::size_t>(
        1, static_cast<std::size_t>(filled * static_cast<double>(point_of_pixel.size()) /
                                    static_cast<double>(std::max(1, options.max_points))));
    samples.reserve(static_cast<std::size_t>(options.max_points) + 1);
    for (std::size_t px = 0; px < point_of_pixel.size(); px += step)
      if (point_of_pixel[px] >= 0) samples.push_back(points[static_cast<std::size_t>(point_of_pixel[px])]);
  }
  if (samples.empty()) return result;

  const BeamLookup beams(sensor);
  const int cols = previous.cols;
  Pose T = initial;
  double width = options.initial_width;
  int pairs = 0;
  for (int it = 0; it < options.iterations; ++it) {
    const double w2 = width * width;
    const NormalEquations eq = tbb::parallel_deterministic_reduce(  // same sums every run
        tbb::blocked_range<std::size_t>(0, samples.size(), 1024), NormalEquations{},
        [&](const tbb::blocked_range<std::size_t>& range, NormalEquations acc) {
          for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const Vec3 q = T * samples[k];
            const int row = beams.row(q);
            if (row < 0) continue;
            const int col = azimuth_column(q.x(), q.y(), cols);
            const auto px = static_cast<std::size_t>(row * cols + col);
            const Vec3f n = surface_normal(previous, row, col);
            if (n.isZero()) continue;
            const Vec3 d = q - previous.point[px].cast<double>();
            const Vec3 nd = n.cast<double>();
            const double e = nd.dot(d);
            // Pairs on another surface: too far along the surface as well as across it.
            if (e * e >= w2 || d.norm() > 0.1 * q.norm() + 2.0 * width) continue;
            const double s = 1.0 - e * e / w2;
            const double weight = s * s;  // Tukey
            Vec6 J;
            J.head<3>() = q.cross(nd);
            J.tail<3>() = nd;
            acc.H.noalias() += weight * J * J.transpose();
            acc.g.noalias() += weight * e * J;
            ++acc.pairs;
          }
          return acc;
        },
        [](NormalEquations a, const NormalEquations& b) {
          a.add(b);
          return a;
        });
    pairs = eq.pairs;
    if (pairs < 6) return result;
    const Vec6 delta = eq.H.ldlt().solve(-eq.g);
    if (!delta.allFinite()) return result;
    T = normalized(exp_se3(delta) * T);
    const bool narrowest = width <= options.final_width;
    width = std::max(options.final_width, 0.5 * width);
    if (narrowest && delta.head<3>().norm() < 1e-4 && delta.tail<3>().norm() < 1e-3) break;  // converged
  }
  result.pairs = pairs;
  result.valid = static_cast<double>(pairs) >= options.min_inlier_ratio * static_cast<double>(samples.size());
  if (result.valid) result.T = T;
  return result;
}

}  // namespace dloam
