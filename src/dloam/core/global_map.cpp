// Per-keyframe global map with a world voxel occupancy set (see global_map.hpp).
#include "dloam/core/global_map.hpp"

#include <cmath>
#include <string>

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {
constexpr std::int64_t kHalfRange = std::int64_t{1} << 20;  // voxels per axis each side of 0

std::uint64_t axis_key(double x, double leaf) {
  const double v = std::floor(x / leaf);
  if (!(std::abs(v) < static_cast<double>(kHalfRange)))
    throw InputError("global map: point at " + std::to_string(x) + " m is outside the map's range");
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) + kHalfRange);
}
}  // namespace

bool GlobalMap::occupy(const Vec3& world) {
  if (leaf_ <= 0.0) return true;
  const std::uint64_t key =
      axis_key(world.x(), leaf_) << 42 | axis_key(world.y(), leaf_) << 21 | axis_key(world.z(), leaf_);
  return occupied_.insert(key).second;
}

void GlobalMap::add(std::size_t keyframe, const std::vector<Vec3>& points, const Pose& pose) {
  if (local_.size() <= keyframe) local_.resize(keyframe + 1);
  auto& kept = local_[keyframe];
  for (const Vec3& p : points)
    if (occupy(pose * p)) kept.push_back(p.cast<float>());
}

void GlobalMap::move(const std::vector<Pose>& keyframe_poses) {
  occupied_.clear();
  for (std::size_t k = 0; k < local_.size() && k < keyframe_poses.size(); ++k)
    for (const Eigen::Vector3f& p : local_[k]) occupy(keyframe_poses[k] * p.cast<double>());
}

std::vector<Vec3> GlobalMap::points(const std::vector<Pose>& keyframe_poses) const {
  std::vector<Vec3> world;
  world.reserve(size());
  for (std::size_t k = 0; k < local_.size() && k < keyframe_poses.size(); ++k)
    for (const Eigen::Vector3f& p : local_[k]) world.push_back(keyframe_poses[k] * p.cast<double>());
  return voxel_downsample_points(world, leaf_);
}

std::size_t GlobalMap::size() const {
  std::size_t n = 0;
  for (const auto& v : local_) n += v.size();
  return n;
}

}  // namespace dloam
