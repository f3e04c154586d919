#include "dloam/core/deskew.hpp"

#include <algorithm>
#include <cmath>

#include "dloam/core/range_image.hpp"
#include "dloam/core/se3.hpp"

namespace dloam {

SweepMotion ScanInterval::sweep_motion(const Pose& step) const {
  if (previous_dt > 0.0) {
    const Vec6 v = log_se3(step) / dt;
    // v is the mean velocity between the middles of the two sweeps; the one before was measured
    // (dt + previous_dt) / 2 earlier, and this sweep's reference time is dt / 2 later.
    Vec6 a = (v - previous_velocity) / (0.5 * (dt + previous_dt));
    const double angular = a.head<3>().norm(), linear = a.tail<3>().norm();
    if (angular > max_angular_acceleration) a.head<3>() *= max_angular_acceleration / angular;
    if (linear > max_acceleration) a.tail<3>() *= max_acceleration / linear;
    // The velocity at the reference time, reached from the previous one at that (bounded) rate.
    SweepMotion m;
    m.xi = sweep * (previous_velocity + (0.5 * (dt + previous_dt) + 0.5 * dt) * a);
    m.acceleration = sweep * sweep * a;
    return m;
  }
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

namespace {

/// The motion at the middle of each of `bins` equal slices of the sweep, and the slice of a time.
struct SliceTable {
  std::vector<Pose> poses;
  SliceTable(const SweepMotion& motion, double reference_time, int bins)
      : poses(static_cast<std::size_t>(bins)) {
    for (int b = 0; b < bins; ++b)
      poses[static_cast<std::size_t>(b)] = motion.at((b + 0.5) / bins - reference_time);
  }
  [[nodiscard]] const Pose& at(double t) const {
    const int bins = static_cast<int>(poses.size());
    return poses[static_cast<std::size_t>(std::clamp(static_cast<int>(t * bins), 0, bins - 1))];
  }
};

}  // namespace

std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const SweepMotion& motion, double reference_time, int bins) {
  const SliceTable table(motion, reference_time, bins);
  std::vector<Vec3> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = table.at(times[i]) * points[i];
  return out;
}

std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const std::vector<int>& indices, const SweepMotion& motion, double reference_time,
                         int bins) {
  const SliceTable table(motion, reference_time, bins);
  std::vector<Vec3> out;
  out.reserve(indices.size());
  for (int i : indices) {
    const auto k = static_cast<std::size_t>(i);
    out.push_back(table.at(times[k]) * points[k]);
  }
  return out;
}

}  // namespace dloam
