#include "dloam/core/deskew.hpp"

#include <algorithm>
#include <cmath>

#include "dloam/core/range_image.hpp"
#include "dloam/core/se3.hpp"

namespace dloam {

Pose ScanInterval::sweep_motion(const Pose& step) const {
  const double s = sweep / dt;
  return std::abs(s - 1.0) < 1e-9 ? step : scale_motion(step, s);
}

int ScanInterval::missed_scans() const { return std::max(0, static_cast<int>(std::lround(dt / sweep)) - 1); }

std::vector<double> point_times(const PointCloud& cloud, bool use_channel) {
  std::vector<double> t(cloud.size());
  if (use_channel && cloud.has_time()) {
    std::copy(cloud.time.begin(), cloud.time.end(), t.begin());
  } else {
    for (std::size_t i = 0; i < cloud.size(); ++i) t[i] = azimuth_time(cloud.xyz[i].x(), cloud.xyz[i].y());
  }
  return t;
}

std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const Pose& motion, double reference_time, int bins) {
  const Vec6 xi = log_se3(motion);
  std::vector<Pose> table(static_cast<std::size_t>(bins));
  for (int b = 0; b < bins; ++b) {
    const double t = (b + 0.5) / bins;
    table[static_cast<std::size_t>(b)] = exp_se3((t - reference_time) * xi);
  }
  std::vector<Vec3> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int b = std::clamp(static_cast<int>(times[i] * bins), 0, bins - 1);
    out[i] = table[static_cast<std::size_t>(b)] * points[i];
  }
  return out;
}

std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const std::vector<int>& indices, const Pose& motion, double reference_time) {
  const Vec6 xi = log_se3(motion);
  std::vector<Vec3> out;
  out.reserve(indices.size());
  for (int i : indices) {
    const auto k = static_cast<std::size_t>(i);
    out.push_back(exp_se3((times[k] - reference_time) * xi) * points[k]);
  }
  return out;
}

}  // namespace dloam
