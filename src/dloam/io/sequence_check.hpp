// Full validation of a sequence folder for `dloam check`: reads every scan, label file, pose,
// time and the calibration, collects every problem (each naming its file) instead of stopping
// at the first, and summarises what ground truth the sequence has. A rosbag (a file, with an
// optional topic) is checked message by message.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/sensor_estimate.hpp"

namespace dloam::io {

/// A scan with fewer points than this is reported as degenerate (odometry needs features).
inline constexpr std::size_t kMinScanPoints = 100;

struct SequenceReport {
  std::string dir;
  std::string scan_format;  ///< "KITTI .bin" or "PCD", "PointCloud2" (bags) or "decoded" (raw packets)
  std::string source;       ///< recordings (bags, captures): ScanSource::describe()
  std::optional<SensorConfig> recording_sensor;  ///< the sensor model a raw-packet recording gives
  std::size_t scans = 0, scans_ok = 0;
  std::size_t min_points = 0, max_points = 0;
  double mean_points = 0.0;
  std::size_t points_with_time = 0;  ///< scans that carry a per-point time channel
  std::size_t dropped_points = 0;    ///< no-return (NaN) points dropped by the reader, all scans
  std::size_t degenerate_scans = 0;  ///< readable scans too small or too concentrated to register
  bool has_labels = false;
  std::size_t label_files = 0, labelled_points = 0, moving_points = 0, ignored_points = 0;
  bool has_poses = false;
  std::size_t pose_count = 0;
  double path_length_m = 0.0;  ///< of the LiDAR (Tr applied when calib has Tr)
  bool has_calib = false, calib_has_Tr = false;
  std::vector<std::string> calib_keys;
  bool has_times = false;
  std::size_t time_count = 0;
  double first_time = 0.0, last_time = 0.0;
  std::optional<SensorModelEstimate> sensor;  ///< estimated from up to 12 scans spread over the sequence
  std::string sensor_error;                   ///< why there is no estimate (not a problem of the files)
  std::optional<SensorFit> fit;       ///< of the first scan with enough points, against the sensor checked
  std::string fit_sensor;             ///< the sensor model `fit` was computed for
  std::vector<std::string> problems;  ///< one InputError message per problem, naming the file
  std::vector<std::string> warnings;  ///< oddities that do not stop `dloam run` (degenerate scans, gaps)
};

struct CheckOptions {
  InputOptions input;  ///< how a recording is read (topic, calibration, port ...)
  /// The sensor `dloam run` would use (--preset / --config): scans that do not fit it are
  /// problems, as in `dloam run`. Without it the scans are compared with the recording's sensor
  /// model or the preset nearest to the estimate, and a poor fit is a warning.
  std::optional<SensorConfig> sensor;
  SensorEstimationConfig estimation;  ///< its vertical-angle correction is applied to the points
  std::function<void(const std::string&)> on_problem, on_warning;  ///< see each as it is found
};

/// Checks everything. Never throws for bad data: a folder that cannot be listed is itself reported
/// as a problem, and so is any exception while reading a file. The sensor model is estimated from
/// up to 12 scans spread over the sequence.
SequenceReport check_sequence(const std::string& dir, const CheckOptions& options);
/// The same with only `on_problem` to see the problems.
SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem = {},
                              const std::string& topic = {}, const SensorEstimationConfig& estimation = {});
/// Same for a recording read with `input` (topic, calibration, port ...).
SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem,
                              const InputOptions& input, const SensorEstimationConfig& estimation = {});

}  // namespace dloam::io
