// Full validation of a sequence folder for `dloam check`: reads every scan, label file, pose,
// time and the calibration, collects every problem (each naming its file) instead of stopping
// at the first, and summarises what ground truth the sequence has. A rosbag (a file, with an
// optional topic) is checked message by message.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dloam/io/kitti.hpp"
#include "dloam/io/sensor_estimate.hpp"

namespace dloam::io {

struct SequenceReport {
  std::string dir;
  std::string scan_format;  ///< "KITTI .bin" or "PCD", "PointCloud2" (bags) or "decoded" (raw packets)
  std::string source;       ///< recordings (bags, captures): ScanSource::describe()
  std::optional<SensorConfig> recording_sensor;  ///< the sensor model a raw-packet recording gives
  std::size_t scans = 0, scans_ok = 0;
  std::size_t min_points = 0, max_points = 0;
  double mean_points = 0.0;
  std::size_t points_with_time = 0;  ///< scans that carry a per-point time channel
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
  std::vector<std::string> problems;          ///< one InputError message per problem, naming the file
};

/// Checks everything; `on_problem` (optional) sees each problem as it is found. Never throws
/// for bad data: a folder that cannot be listed is itself reported as a problem. The sensor model
/// is estimated with `estimation` (its vertical-angle correction applied to the points).
SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem = {},
                              const std::string& topic = {}, const SensorEstimationConfig& estimation = {});
/// Same for a recording read with `input` (topic, calibration, port ...).
SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem,
                              const InputOptions& input, const SensorEstimationConfig& estimation = {});

}  // namespace dloam::io
