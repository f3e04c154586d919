// Beam table fit (elevation + origin height per beam) from the point order of ring-by-ring scans.
#include "dloam/core/beam_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace dloam {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr double kTurnSlack = 0.3 * kDeg;  ///< azimuth jitter at the end of a turn

/// Least squares z = dz + h t over the points with |residual| below `limit` (all: infinity).
Eigen::Vector2d line_fit(const std::vector<float>& h, const std::vector<float>& z,
                         const Eigen::Vector2d& prev, double limit, std::size_t& used) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  used = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (std::abs(z[i] - prev(0) - h[i] * prev(1)) > limit) continue;
    const Eigen::Vector2d a(1.0, h[i]);
    A += a * a.transpose();
    b += a * z[i];
    ++used;
  }
  return used >= 2 ? Eigen::Vector2d(A.ldlt().solve(b)) : prev;
}
}  // namespace

std::vector<int> rings_from_point_order(const std::vector<Vec3>& points) {
  std::vector<double> unwrapped(points.size(), 0.0);
  double u = 0.0, last = 0.0;
  bool started = false;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (p.head<2>().squaredNorm() > 0.0) {  // the origin has no azimuth: keeps the previous one
      const double a = std::atan2(p.y(), p.x());
      if (started) u += std::remainder(a - last, 2.0 * M_PI);
      last = a;
      started = true;
    }
    unwrapped[i] = u;
  }
  const double direction = u < 0.0 ? -1.0 : 1.0;  // counter-clockwise (KITTI) or clockwise
  std::vector<int> ring(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    ring[i] = static_cast<int>(std::floor((direction * unwrapped[i] + kTurnSlack) / (2.0 * M_PI)));
  return ring;
}

void BeamTableFit::add(const std::vector<Vec3>& points, const std::string& source) {
  const int n = sensor_.N_scan;
  const std::vector<int> ring = rings_from_point_order(points);
  const int found = ring.empty() ? 0 : *std::max_element(ring.begin(), ring.end()) + 1;
  const auto beyond = std::count_if(ring.begin(), ring.end(), [&](int r) { return r >= n; });
  const bool backwards = std::any_of(ring.begin(), ring.end(), [](int r) { return r < 0; });
  if (found < n || backwards || static_cast<double>(beyond) > 0.01 * static_cast<double>(points.size()))
    throw InputError(source + ": the point order gives " + std::to_string(found) +
                     " turns of azimuth, the sensor has " + std::to_string(n) +
                     " beams (fitting beams needs scans stored ring by ring, as KITTI .bin)");
  h_.resize(static_cast<std::size_t>(n));
  z_.resize(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = points[i].norm();
    if (ring[i] >= n || !(r >= sensor_.min_range && r <= sensor_.max_range)) continue;
    h_[static_cast<std::size_t>(ring[i])].push_back(static_cast<float>(points[i].head<2>().norm()));
    z_[static_cast<std::size_t>(ring[i])].push_back(static_cast<float>(points[i].z()));
  }
}

std::vector<BeamTableFit::Beam> BeamTableFit::fit() const {
  std::vector<Beam> beams;
  for (std::size_t k = 0; k < h_.size(); ++k) {
    if (h_[k].size() < 100)
      throw InputError("beam fit: ring " + std::to_string(k) + " has only " + std::to_string(h_[k].size()) +
                       " points in range (need 100)");
    // Robust: refit on the points within 3 median absolute residuals (at least 2 cm), which drops
    // the few points of neighbouring rings taken at the turn and mixed pixels.
    std::size_t used = 0;
    Eigen::Vector2d line = line_fit(h_[k], z_[k], Eigen::Vector2d::Zero(), INFINITY, used);
    double limit = INFINITY;
    std::vector<float> res(h_[k].size());
    for (int iteration = 0; iteration < 4; ++iteration) {
      for (std::size_t i = 0; i < res.size(); ++i) res[i] = std::abs(z_[k][i] - line(0) - h_[k][i] * line(1));
      auto mid = res.begin() + static_cast<std::ptrdiff_t>(res.size() / 2);
      std::nth_element(res.begin(), mid, res.end());
      limit = std::max(3.0 * *mid, 0.02);
      line = line_fit(h_[k], z_[k], line, limit, used);
    }
    double sum = 0.0;
    std::size_t inliers = 0;
    for (std::size_t i = 0; i < res.size(); ++i) {
      const double e = z_[k][i] - line(0) - h_[k][i] * line(1);
      if (std::abs(e) > limit) continue;
      sum += e * e;
      ++inliers;
    }
    const double rms = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(inliers, 1)));
    beams.push_back({static_cast<int>(k), std::atan(line(1)) / kDeg, line(0), rms, used});
  }
  std::sort(beams.begin(), beams.end(),
            [](const Beam& a, const Beam& b) { return a.elevation_deg < b.elevation_deg; });
  return beams;
}

SensorConfig BeamTableFit::fitted_sensor() const {
  SensorConfig s = sensor_;
  s.beam_elevations_deg.clear();
  s.beam_vertical_offsets_m.clear();
  for (const Beam& b : fit()) {
    s.beam_elevations_deg.push_back(std::round(b.elevation_deg * 1000.0) / 1000.0);
    s.beam_vertical_offsets_m.push_back(std::round(b.offset_m * 1000.0) / 1000.0);
  }
  s.Pit_bottom = s.beam_elevations_deg.front();
  s.fov_top = s.beam_elevations_deg.back();
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("beam fit: the fitted table is not valid: ") + e.what());
  }
  return s;
}

}  // namespace dloam
