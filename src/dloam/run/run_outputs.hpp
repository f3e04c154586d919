// The output folder of a run, as `dloam run`, `dloam_node` and the Python module write it:
//   poses.txt       KITTI poses of the mapping-refined trajectory (camera frame when a KITTI Tr is
//                   given, like the input's poses.txt; else the sensor frame)
//   poses_tum.txt   the same with the scan stamps (TUM format)
//   calib.txt       the Tr the poses were written with (when given)
//   poses_gt.txt    the ground-truth poses of the scans run, in the frame of poses.txt (when known)
//   map.ply         the downsampled global map (first scan's sensor frame)
//   moving.ply      the points labelled moving, at their scans' final poses, voxel-downsampled
//   timing.csv      milliseconds per scan and module, feature counts and flags
//   config.yaml     the full configuration used (the detector resolved)
//   labels/         NNNNNN.label per scan when a detector is on
//   metrics.json    tracking, degenerate scans; odometry against ground-truth poses; MOS and map
//                   statistics against ground-truth labels
// Every file is written atomically (temp file + rename). finish() writes them from what it can
// still get when the pipeline has failed (the real-time poses, an empty map), and says so.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/metrics.hpp"
#include "dloam/run/scan_checks.hpp"

namespace dloam::run {

struct OutputOptions {
  std::string dir;
  /// KITTI calib Tr (LiDAR -> camera 0): poses are written in the camera frame. Empty: sensor frame.
  std::optional<Pose> camera_Tr;
  std::vector<double> lengths;    ///< segment lengths of metrics.json (empty: segment_options' choice)
  bool labels = true;             ///< write labels/ when the detector is on
  double moving_leaf_size = 0.2;  ///< m: voxel size of moving.ply (per scan)
};

/// Where a scan came from: names its per-scan outputs and its warnings.
struct ScanOrigin {
  std::string name;  ///< labels/NAME.label; empty: io::scan_name(the result's index)
  std::string file;  ///< named in warnings; empty: the name
  /// What the reader dropped (no-return points): the labels are written one per point of the file,
  /// the dropped ones unlabelled.
  const io::ScanInfo* info = nullptr;
};

/// What finish() wrote, for the caller to print.
struct RunSummary {
  std::size_t scans = 0;
  std::size_t map_points = 0;
  std::size_t moving_points = 0;
  std::size_t loop_closures = 0;
  std::vector<Pose> trajectory;     ///< sensor frame, one per scan
  std::vector<ScanResult> results;  ///< per scan, without the per-point vectors
  std::optional<eval::OdometryResult> odometry;
  eval::SegmentOptions segments;
  std::optional<LabelStats> labels;
  nlohmann::json metrics;  ///< what metrics.json holds
  /// The scans' checks: degenerate ones, points without a return.
  std::size_t degenerate = 0, without_usable_points = 0, dropped_points = 0;
  bool all_degenerate_after_first = false;
  /// What the pipeline could not give at the end (refined poses, map): the outputs hold the
  /// real-time poses / an empty map instead. Empty when all went well.
  std::vector<std::string> problems;
};

class RunOutputs {
 public:
  /// Creates the folder (and labels/ when a detector is on) and writes config.yaml. `config`
  /// must have its detector resolved (not auto).
  RunOutputs(OutputOptions options, const PipelineConfig& config);

  /// After each scan, in order: writes its labels, keeps its real-time pose, its moving points
  /// (from `cloud`, the scan read, in the result's point order) and its timing; flags `r` when it is
  /// degenerate (DegenerateScans); with `gt` (the scan's ground-truth labels) the label
  /// statistics. `r` keeps its per-point vectors. Returns a warning for the caller to show (a
  /// degenerate scan), or empty.
  std::string add(ScanResult& r, const PointCloud& cloud, const std::vector<Label>* gt = nullptr,
                  const ScanOrigin& origin = {});
  /// poses.txt and poses_tum.txt of the real-time poses of the scans added so far: a checkpoint.
  void write_poses() const;
  /// Writes every file from the pipeline's final trajectory and map. `gt_lidar_poses`: the
  /// ground truth of the scans added (sensor frame), for poses_gt.txt and the odometry metrics.
  RunSummary finish(Pipeline& pipeline, const std::vector<Pose>* gt_lidar_poses = nullptr);

  /// Removes what the constructor wrote (config.yaml, calib.txt, an empty labels/): for a run that
  /// failed before its first scan.
  void discard() const;

  [[nodiscard]] std::size_t scans() const { return results_.size(); }
  [[nodiscard]] const std::vector<ScanResult>& results() const { return results_; }
  [[nodiscard]] const OutputOptions& options() const { return options_; }

 private:
  [[nodiscard]] std::vector<Pose> in_output_frame(const std::vector<Pose>& lidar_poses) const;
  void write_poses(const std::vector<Pose>& lidar_poses) const;

  OutputOptions options_;
  bool labels_on_ = false;
  DegenerateScans degenerate_;
  std::vector<ScanResult> results_;        ///< per-point vectors cleared
  std::vector<Pose> realtime_poses_;       ///< per scan
  std::vector<std::vector<Vec3>> moving_;  ///< per scan, sensor frame
  std::optional<LabelStats> label_stats_;  ///< when ground-truth labels were given
};

}  // namespace dloam::run
