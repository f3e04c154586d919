// The DLOAM pipeline (paper Fig. 1): segmentation -> (pre-registration, de-skew) -> dynamic-object
// detection -> feature extraction from static points -> scan-to-scan odometry -> scan-to-map
// mapping -> transform integration. One call per scan, in order; deterministic.
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/mapping.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/types.hpp"
#include "dloam/pipeline/config.hpp"
#include "dloam/pipeline/dynamic_stage.hpp"
#include "dloam/pipeline/timing.hpp"

namespace dloam {

struct ScanResult {
  std::size_t index = 0;
  Pose pose = Pose::Identity();             ///< integrated world pose (sensor frame at mid-sweep)
  Pose odometry_pose = Pose::Identity();    ///< odometry-only pose
  std::vector<Label> labels;                ///< per input point: 9 static / 251 moving (detector on)
  std::vector<std::size_t> edge_features;   ///< input point indices of F_e
  std::vector<std::size_t> plane_features;  ///< input point indices of F_p
  std::size_t n_edges = 0, n_planes = 0;    ///< |F_e|, |F_p|
  std::vector<std::size_t> map_points;      ///< input indices of the points added to the global map
  bool mapped = false;                      ///< mapping ran on this scan
  bool keyframe = false;
  bool loop_closed = false;  ///< a loop closure corrected the keyframes at this scan
  bool degenerate = false;
  int num_dynamic = 0;                ///< dynamic clusters (detector on)
  int pseudo_static = 0;              ///< type-2 pseudo-static objects (dynamic -> static)
  bool coarse_valid = false;          ///< pre-registration gave T_coarse
  std::size_t rejected_features = 0;  ///< removed by the pseudo-static rejection
  ModuleTimes times;
};

class Pipeline {
 public:
  explicit Pipeline(const PipelineConfig& config);
  ScanResult process(const PointCloud& cloud);

  [[nodiscard]] const PipelineConfig& config() const { return config_; }
  [[nodiscard]] std::vector<Vec3> global_map() const { return mapper_.global_map(); }
  /// The poses reported so far (`ScanResult::pose`, one per scan in order), each moved with its
  /// keyframe when a loop closure corrected the keyframes afterwards.
  [[nodiscard]] std::vector<Pose> corrected_trajectory(const std::vector<Pose>& reported) const {
    return mapper_.corrected_trajectory(reported);
  }
  [[nodiscard]] std::size_t loop_closures() const { return mapper_.loops().size(); }

 private:
  PipelineConfig config_;
  ScanToScanOdometry odometry_;
  Mapper mapper_;
  std::unique_ptr<DynamicStage> dynamic_;  ///< geometric detector, when on
  std::size_t count_ = 0;
  Pose odometry_pose_ = Pose::Identity();
  Pose correction_ = Pose::Identity();  ///< mapping pose * odometry pose^-1 (transform integration)
  Pose last_pose_ = Pose::Identity();
  Pose velocity_ = Pose::Identity();  ///< last inter-scan motion, the constant-velocity prediction
};

}  // namespace dloam
