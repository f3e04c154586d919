// Per-keyframe global map with a world voxel occupancy set (see global_map.hpp).
#include "dloam/core/global_map.hpp"

#include <cmath>
#include <string>

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {
constexpr double kKeyRange = 2.0e9;  // voxels per axis each side of 0 (32-bit keys)

std::int32_t axis_key(double x, double leaf) {
  const double v = std::floor(x / leaf);
  if (!(std::abs(v) < kKeyRange))
    throw InputError("global map: point at " + std::to_string(x) + " m is outside the map's range (" +
                     std::to_string(kKeyRange * leaf / 1000.0) + " km at map_leaf_size " +
                     std::to_string(leaf) + " m)");
  return static_cast<std::int32_t>(v);
}
}  // namespace

std::size_t GlobalMap::KeyHash::operator()(const Key& k) const {
  const std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(k[0])) * 73856093ULL ^
                          static_cast<std::uint64_t>(static_cast<std::uint32_t>(k[1])) * 19349669ULL ^
                          static_cast<std::uint64_t>(static_cast<std::uint32_t>(k[2])) * 83492791ULL;
  return static_cast<std::size_t>((h ^ (h >> 29)) * 0x9E3779B97F4A7C15ULL);
}

bool GlobalMap::occupy(const Vec3& world) {
  if (leaf_ <= 0.0) return true;
  return occupied_
      .insert(Key{axis_key(world.x(), leaf_), axis_key(world.y(), leaf_), axis_key(world.z(), leaf_)})
      .second;
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
