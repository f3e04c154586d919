#include "dloam/core/local_map.hpp"

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

const FeatureMap& LocalMap::around(const Vec3& position) {
  // Members: keyframes within the radius, plus the last few (always relevant, even when turning).
  std::vector<std::size_t> members;
  const std::size_t n = keyframes_.size();
  constexpr std::size_t kRecent = 10;
  for (std::size_t i = 0; i < n; ++i) {
    const bool recent = i + kRecent >= n;
    if (recent || (keyframes_[i].pose.translation() - position).norm() < radius_) members.push_back(i);
  }
  if (!dirty_ && members == members_) return map_;
  members_ = std::move(members);
  dirty_ = false;
  std::vector<Vec3> edges, planes;
  for (std::size_t i : members_) {
    const Keyframe& kf = keyframes_[i];
    for (const Vec3& p : kf.edges) edges.push_back(kf.pose * p);
    for (const Vec3& p : kf.planes) planes.push_back(kf.pose * p);
  }
  map_.edges.build(voxel_downsample_points(edges, edge_leaf_));
  map_.planes.build(voxel_downsample_points(planes, plane_leaf_));
  return map_;
}

}  // namespace dloam
