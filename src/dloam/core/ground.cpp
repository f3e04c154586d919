// Ground extraction (paper eq. 7) and least-squares ground plane.
#include "dloam/core/ground.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace dloam {

namespace {

constexpr double kDeg = M_PI / 180.0;

// Least-squares plane through the points (smallest principal axis of their covariance).
// Uses every step-th point: a few thousand are plenty.
void fit_plane(const std::vector<Vec3>& points, const std::vector<int>& idx, GroundResult& out) {
  if (idx.size() < 3) return;
  const std::size_t step = std::max<std::size_t>(1, idx.size() / 4000);
  Vec3 mean = Vec3::Zero();
  double count = 0.0;
  for (std::size_t k = 0; k < idx.size(); k += step, count += 1.0)
    mean += points[static_cast<std::size_t>(idx[k])];
  mean /= count;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < idx.size(); k += step) {
    const Vec3 d = points[static_cast<std::size_t>(idx[k])] - mean;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  if (solver.info() != Eigen::Success || solver.eigenvalues()(1) <= 0.0) return;  // degenerate (a line)
  Vec3 n = solver.eigenvectors().col(0).normalized();
  if (n.z() < 0.0) n = -n;
  out.normal = n;
  out.height = -n.dot(mean);  // plane: n.p + height = 0; the origin is `height` above it
  out.plane_valid = true;
}

}  // namespace

int ground_search_rows(const SensorConfig& sensor, const GroundConfig& config) {
  if (config.N_ground_rows > 0) return std::min(config.N_ground_rows, sensor.N_scan);
  int rows = 0;
  while (rows < sensor.N_scan && sensor.beam_elevation_deg(rows) <= -1.0) ++rows;
  return rows;
}

GroundResult extract_ground(const std::vector<Vec3>& points, const RangeImage& image,
                            const SensorConfig& sensor, const GroundConfig& config, double plane_radius,
                            double max_height) {
  GroundResult out;
  out.mask.assign(image.range.size(), 0);
  const int rows = std::min(ground_search_rows(sensor, config), image.rows);
  const double tan_max = std::tan(config.ground_pitch_deg * kDeg), tan2_max = tan_max * tan_max;
  std::vector<double> elev(static_cast<std::size_t>(rows));
  for (int v = 0; v < rows; ++v) elev[static_cast<std::size_t>(v)] = sensor.beam_elevation_deg(v) * kDeg;
  // Pairs (v, w) with w = v + 1, or v + 2 across an empty pixel (range-image holes).
  for (int v = 0; v + 1 < rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const int a = image.point_at(v, u);
      if (a < 0) continue;
      int w = v + 1;
      if (image.point_at(w, u) < 0 && w + 1 < rows) ++w;
      const int b = image.point_at(w, u);
      if (b < 0) continue;
      const Vec3& pa = points[static_cast<std::size_t>(a)];
      const Vec3& pb = points[static_cast<std::size_t>(b)];
      const Vec3 d = pb - pa;
      // |atan2(dz, hypot(dx, dy))| < threshold, written without the atan2 (and the root).
      if (!(d.z() * d.z() < tan2_max * d.head<2>().squaredNorm())) continue;
      // Two beams `gap` apart hit a surface below the sensor at least r * gap apart, the upper
      // one farther out. Pairs closer than half that (or reversed) are a near vertical object
      // whose points the range image put in swapped or duplicated rows, not ground.
      const double gap = std::abs(elev[static_cast<std::size_t>(w)] - elev[static_cast<std::size_t>(v)]);
      const double outward = pb.head<2>().norm() - pa.head<2>().norm();
      if (outward < 0.5 * gap * image.range[static_cast<std::size_t>(image.pixel(v, u))]) continue;
      out.mask[static_cast<std::size_t>(image.pixel(v, u))] = 1;
      out.mask[static_cast<std::size_t>(image.pixel(w, u))] = 1;
    }
  }
  const double radius2 = plane_radius * plane_radius;
  std::vector<int> support;  // ground points within plane_radius, or all when fewer than 50
  for (std::size_t px = 0; px < out.mask.size(); ++px) {
    if (!out.mask[px]) continue;
    ++out.num_ground;
    const int i = image.point_of_pixel[px];
    if (points[static_cast<std::size_t>(i)].head<2>().squaredNorm() <= radius2) support.push_back(i);
  }
  if (support.size() < 50) {
    support.clear();
    for (std::size_t px = 0; px < out.mask.size(); ++px)
      if (out.mask[px]) support.push_back(image.point_of_pixel[px]);
  }
  fit_plane(points, support, out);
  // Two refits on the points within kInlier of the plane, so curbs, sidewalks and the odd flat
  // object top do not tilt it.
  constexpr double kInlier = 0.15;
  std::vector<int> inliers;
  for (int iter = 0; iter < 2 && out.plane_valid; ++iter) {
    inliers.clear();
    for (int i : support)
      if (std::abs(out.normal.dot(points[static_cast<std::size_t>(i)]) + out.height) < kInlier)
        inliers.push_back(i);
    if (inliers.size() < 3 || inliers.size() == support.size()) break;
    support.swap(inliers);
    fit_plane(points, support, out);
  }
  // Flat tops of objects (a van's roof, a bicycle's frame) also pass eq. 7: near the sensor,
  // where the plane holds, pixels more than max_height above it are not ground.
  if (!out.plane_valid) return out;
  for (std::size_t px = 0; px < out.mask.size(); ++px) {
    if (!out.mask[px]) continue;
    const Vec3& p = points[static_cast<std::size_t>(image.point_of_pixel[px])];
    if (p.head<2>().squaredNorm() <= radius2 && out.normal.dot(p) + out.height > max_height) {
      out.mask[px] = 0;
      --out.num_ground;
    }
  }
  return out;
}

}  // namespace dloam
