// Guessing which LiDAR recorded a sequence, for `dloam check`: an elevation histogram of the
// points gives the vertical field of view (robust percentiles) and the number of resolved beams
// (histogram peaks); the closest built-in sensor preset is the one whose field of view and beam
// count fit best.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam::io {

/// Histogram of point elevations atan2(z, hypot(x, y)) in degrees, -90..90.
struct ElevationHistogram {
  double bin_deg = 0.05;
  std::vector<std::size_t> counts = std::vector<std::size_t>(3600, 0);
  std::size_t total = 0;
  /// Adds the points farther than `min_range` (m) horizontally.
  void add(const PointCloud& cloud, double min_range = 1.0);
  /// Elevation (deg) below which a fraction `q` of the points lies.
  [[nodiscard]] double quantile(double q) const;
};

struct SensorEstimate {
  double lowest_deg = 0.0, highest_deg = 0.0;  ///< 0.05 % and 99.95 % elevation quantiles
  int resolved_beams = 0;    ///< histogram peaks: exact for sharp beams; blurred beams (KITTI) merge or split
  std::string preset;        ///< closest built-in preset
  double fov_overlap = 0.0;  ///< intersection / union of observed and preset fields of view
};

/// Throws InputError when the histogram is empty.
SensorEstimate estimate_sensor(const ElevationHistogram& histogram);

/// How one scan fits a sensor model, the test `dloam run` and `dloam check` share: the points
/// within [min_range, max_range] (vertical-angle correction applied) and how many of them fall on
/// a beam of the model's range image.
struct SensorFit {
  std::size_t points = 0, in_range = 0, inside = 0;
};
SensorFit sensor_fit(const PointCloud& cloud, const SensorConfig& sensor);
/// A scan needs this many points in range to judge the fit by.
inline constexpr std::size_t kMinFitPoints = 1000;
/// "<file>: only N% of the points lie inside the vertical field of view ..." when fewer than 90 %
/// of the points in range fit; empty when they fit or there are fewer than kMinFitPoints.
std::string sensor_fit_problem(const SensorFit& fit, const SensorConfig& sensor, const std::string& file);

}  // namespace dloam::io
