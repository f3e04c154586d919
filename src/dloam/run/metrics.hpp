// metrics.json of a run: the odometry against ground-truth poses (KITTI devkit relative error,
// ATE, RPE), the moving-object segmentation against ground-truth labels (SemanticKITTI MOS IoU,
// object IoU), the map's share of moving points and Table III's effective features, and how the
// tracking went. The same keys as `dloam eval odometry|mos --json`.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dloam/eval/mos_metrics.hpp"
#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/pipeline/pipeline.hpp"

namespace dloam::run {

/// Segment options: the given lengths (every frame a start unless `step` > 0), else the devkit's
/// 100..800 m every 10 frames, or 5,10,20,30 m every frame when the path is shorter than 200 m.
eval::SegmentOptions segment_options(const std::vector<Pose>& gt, const std::vector<double>& lengths,
                                     std::size_t step = 0);

nlohmann::json odometry_json(const eval::OdometryResult& r, const eval::SegmentOptions& options,
                             const std::string& frame);
/// Point and object counts and IoUs.
nlohmann::json mos_json(const eval::MosResult& r, double object_threshold = 0.5);

/// Ground-truth label statistics of a run, accumulated scan by scan.
struct LabelStats {
  eval::MosResult mos;           ///< the written labels against the ground truth (detector on)
  eval::FeatureCounts features;  ///< Table III: features on static points
  std::uint64_t map_points = 0;  ///< labelled points sent to the global map (before its voxel grid)
  std::uint64_t map_moving = 0;  ///< ... of which the ground truth labels moving
  bool detector = false;         ///< the run wrote labels (mos is meaningful)
  /// `r` still holds its per-point vectors (labels, feature and map indices).
  void add(const std::vector<Label>& gt, const ScanResult& r);
  [[nodiscard]] double map_moving_fraction() const {
    return map_points ? static_cast<double>(map_moving) / static_cast<double>(map_points) : 0.0;
  }
  /// effective_feature_ratio, features_on_labelled_points, map_input_moving_fraction, and `mos`.
  [[nodiscard]] nlohmann::json json() const;
};

/// Gaps in the scan times, steps searched / re-initialised / lost, degenerate scans (odometry:
/// `degenerate_scans`, scan-to-map: `map_degenerate_scans`) with the axes of their unconstrained
/// directions.
nlohmann::json tracking_json(const std::vector<ScanResult>& results);

}  // namespace dloam::run
