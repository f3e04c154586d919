// Keyframes and the local feature map around the current pose (LeGO-LOAM's surrounding
// keyframes): features are stored per keyframe in the sensor frame, so corrected keyframe poses
// (loop closure) move them, and the local map is rebuilt only when the keyframe set changes.
#pragma once

#include <vector>

#include "dloam/core/registration.hpp"

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
      : radius_(radius), edge_leaf_(edge_leaf), plane_leaf_(plane_leaf) {}

  void add(Keyframe kf) {
    keyframes_.push_back(std::move(kf));
    dirty_ = true;
  }
  [[nodiscard]] const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  /// Moves the keyframes (e.g. after a loop closure); the local map is rebuilt on next use.
  void set_poses(const std::vector<Pose>& poses) {
    for (std::size_t i = 0; i < keyframes_.size() && i < poses.size(); ++i) keyframes_[i].pose = poses[i];
    dirty_ = true;
  }
  [[nodiscard]] bool empty() const { return keyframes_.empty(); }

  /// World-frame features of the keyframes within `radius` of `position` (and always the most
  /// recent ones), downsampled; rebuilt when keyframes changed or the pose moved away.
  const FeatureMap& around(const Vec3& position);

 private:
  double radius_, edge_leaf_, plane_leaf_;
  std::vector<Keyframe> keyframes_;
  FeatureMap map_;
  std::vector<std::size_t> members_;
  bool dirty_ = true;
};

}  // namespace dloam
