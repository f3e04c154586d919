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
#include "dloam/pipeline/timing.hpp"

namespace dloam {

struct ScanResult {
  std::size_t index = 0;
  Pose pose = Pose::Identity();           ///< integrated world pose (sensor frame at mid-sweep)
  Pose odometry_pose = Pose::Identity();  ///< odometry-only pose
  std::vector<Label> labels;              ///< per input point: 9 static / 251 moving (detector on)
  std::vector<std::size_t> edge_features;   ///< input point indices of F_e
  std::vector<std::size_t> plane_features;  ///< input point indices of F_p
  bool mapped = false;     ///< mapping ran on this scan
  bool keyframe = false;
  bool degenerate = false;
  ModuleTimes times;
};

class Pipeline {
 public:
  explicit Pipeline(const PipelineConfig& config);
  ScanResult process(const PointCloud& cloud);

  [[nodiscard]] const PipelineConfig& config() const { return config_; }
  [[nodiscard]] std::vector<Vec3> global_map() const { return mapper_.global_map(); }

 private:
  PipelineConfig config_;
  ScanToScanOdometry odometry_;
  Mapper mapper_;
  std::size_t count_ = 0;
  Pose odometry_pose_ = Pose::Identity();
  Pose correction_ = Pose::Identity();  ///< mapping pose * odometry pose^-1 (transform integration)
  Pose last_pose_ = Pose::Identity();
  Pose velocity_ = Pose::Identity();    ///< last inter-scan motion, the constant-velocity prediction
};

}  // namespace dloam
