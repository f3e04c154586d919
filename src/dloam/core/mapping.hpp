// LiDAR mapping (paper III.G, LeGO-LOAM): scan-to-map registration of the current scan's F_e / F_p
// against the local map of keyframes around the predicted pose, keyframe insertion, and the
// downsampled global map of static points.
#pragma once

#include "dloam/core/local_map.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

struct MappingResult {
  Pose pose = Pose::Identity();  ///< refined world pose of the scan
  RegistrationResult registration;
  bool keyframe = false;
};

class Mapper {
 public:
  explicit Mapper(const MappingConfig& config)
      : config_(config), local_(config.local_map_radius, config.edge_leaf_size, config.plane_leaf_size) {}

  /// Features in the scan's sensor frame; `predicted` world pose from the odometry.
  MappingResult process(std::size_t scan, const FeatureSource& features, const Pose& predicted);

  /// Adds static points of a scan (sensor frame) at its world pose to the global map.
  void add_to_global_map(const std::vector<Vec3>& points, const Pose& pose);
  [[nodiscard]] std::vector<Vec3> global_map() const;
  [[nodiscard]] const std::vector<Keyframe>& keyframes() const { return local_.keyframes(); }

 private:
  MappingConfig config_;
  LocalMap local_;
  std::vector<Vec3> global_;       // world-frame static points, compacted by voxel downsampling
  std::size_t compacted_size_ = 0;  // size after the last compaction
};

}  // namespace dloam
