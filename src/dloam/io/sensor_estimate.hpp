// The sensor model of a sequence estimated from its own scans (core/sensor_estimation.hpp), for
// `dloam check` and for `dloam run` with the preset auto: which scans are read, errors naming the
// sequence, the estimate as a YAML `sensor:` section and as lines for the terminal.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/sensor_estimation.hpp"
#include "dloam/core/types.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::io {

/// Up to `count` scan indices spread evenly over [first, last), first included.
std::vector<std::size_t> spread_scan_indices(std::size_t first, std::size_t last, std::size_t count);

/// Reads the scans `indices` of `seq` and estimates its sensor model (scan rate from seq.times).
/// Throws InputError naming the sequence when the scans do not determine a model.
SensorModelEstimate estimate_sequence_sensor(const Sequence& seq, const std::vector<std::size_t>& indices,
                                             const SensorEstimationConfig& config = {});

/// `InputError` of a failed estimate with the sequence named in front.
InputError estimate_error(const std::string& source, const InputError& error);

/// The estimate as the YAML `sensor:` section that --config reads: a comment header (where it
/// comes from, the nearest preset) and every key of the section.
std::string estimated_sensor_yaml(const SensorModelEstimate& estimate, const std::string& source);

/// The estimate for the terminal, one line each: beams and elevations, origin heights, columns,
/// range limits, scan rate, the nearest preset, and what had to be assumed.
std::vector<std::string> describe_estimate(const SensorModelEstimate& estimate);

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
