// Checks a run makes on its scans: whether the sensor model fits the data (judged on the first
// scans with enough points in range), and which scans cannot constrain the odometry (degenerate).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dloam/pipeline/pipeline.hpp"

namespace dloam::run {

/// The sensor model must fit the data: each scan is judged until one has enough points in range
/// (io::kMinFitPoints); a scan that mostly misses the model's vertical field of view throws
/// InputError naming its file and the model (the wrong --preset or sensor config).
class SensorFitCheck {
 public:
  explicit SensorFitCheck(SensorConfig sensor) : sensor_(std::move(sensor)) {}
  void check(const PointCloud& cloud, const std::string& file);
  /// A scan with enough points in range fitted: later scans are not judged.
  [[nodiscard]] bool done() const { return done_; }

 private:
  SensorConfig sensor_;
  bool done_ = false;
};

/// Scans on which the odometry had nothing to hold on to: the predicted motion was kept there.
class DegenerateScans {
 public:
  static constexpr std::size_t kMinFeatures = 10;  ///< per kind (edges, planes), as registration's minimum
  static constexpr std::size_t kListed = 5;        ///< scans warned about one by one; the rest are counted

  explicit DegenerateScans(SensorConfig sensor) : sensor_(std::move(sensor)) {}

  /// Flags `r` (ScanResult::degenerate) when
  /// `cloud` has no usable point (within [min_range, max_range], not at the origin) or too few edge
  /// or plane features. (The odometry flags more scans itself: those where the features leave some
  /// direction unconstrained.) `dropped`: no-return points the reader dropped. Returns a warning
  /// for the first kListed degenerate scans, naming `file`; empty otherwise.
  std::string add(ScanResult& r, const PointCloud& cloud, std::size_t dropped, const std::string& file);

  [[nodiscard]] std::size_t processed() const { return processed_; }
  [[nodiscard]] std::size_t degenerate() const { return scans_.size(); }
  [[nodiscard]] std::size_t without_usable_points() const { return without_points_; }
  [[nodiscard]] std::size_t dropped_points() const { return dropped_points_; }
  /// Every scan after the first of the run is degenerate (and there are at least two).
  [[nodiscard]] bool all_after_first() const { return processed_ > 1 && later_ + 1 == processed_; }
  /// metrics.json's "scans": processed, degenerate, degenerate_scans, without_usable_points,
  /// dropped_no_return_points.
  [[nodiscard]] nlohmann::json json() const;

 private:
  SensorConfig sensor_;
  std::vector<std::size_t> scans_;
  std::size_t later_ = 0;  ///< degenerate scans after the first of the run
  std::size_t without_points_ = 0, dropped_points_ = 0, processed_ = 0;
};

}  // namespace dloam::run
