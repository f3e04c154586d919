// Keyframes and the local feature map around the current pose (LeGO-LOAM's surrounding
// keyframes): features are stored per keyframe in the sensor frame, so corrected keyframe poses
// (loop closure) move them.
//
// The map is kept up to date incrementally: a keyframe that joins is added to the downsampled
// map (one point per voxel, the one nearest its centre: the same points a downsampling of all
// members at once gives), and a keyframe that leaves stays in it until the points of such
// keyframes make up a third of the map's input; only then, and when keyframes move, is the map
// rebuilt from the members. A rebuild downsamples every member's features (about 800 k points on
// a revisited street); a keyframe joining adds only its own.
#pragma once

#include <vector>

#include "dloam/core/registration.hpp"
#include "dloam/core/voxel_grid.hpp"

namespace dloam {

struct Keyframe {
  std::size_t scan = 0;  ///< index of the scan it was taken from
  Pose pose = Pose::Identity();
  std::vector<Vec3> edges;   ///< sensor frame
  std::vector<Vec3> planes;  ///< sensor frame
};

class LocalMap {
 public:
  LocalMap(double radius, double edge_leaf, double plane_leaf)
      : radius_(radius), edges_(edge_leaf), planes_(plane_leaf) {}

  void add(Keyframe kf) { keyframes_.push_back(std::move(kf)); }
  [[nodiscard]] const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  /// Moves the keyframes (e.g. after a loop closure); the local map is rebuilt on next use.
  void set_poses(const std::vector<Pose>& poses) {
    for (std::size_t i = 0; i < keyframes_.size() && i < poses.size(); ++i) keyframes_[i].pose = poses[i];
    dirty_ = true;
  }
  [[nodiscard]] bool empty() const { return keyframes_.empty(); }

  /// World-frame features, downsampled, of the keyframes within `radius` of `position` (and
  /// always the most recent ones), possibly with some that have left since the last rebuild.
  const FeatureMap& around(const Vec3& position);
  /// How many times the map was rebuilt from all its members (for tests and timing).
  [[nodiscard]] std::size_t rebuilds() const { return rebuilds_; }

 private:
  void insert(std::size_t keyframe);

  double radius_;
  std::vector<Keyframe> keyframes_;
  FeatureMap map_;
  VoxelPoints edges_, planes_;  ///< the map's points, before the k-d trees
  std::vector<std::size_t> members_;
  std::vector<bool> in_map_;   ///< per keyframe: its features are in the map
  std::size_t map_input_ = 0;  ///< features of the keyframes in the map
  std::size_t rebuilds_ = 0;
  bool dirty_ = true;  ///< keyframes moved: rebuild
};

}  // namespace dloam
