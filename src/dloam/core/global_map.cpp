// Per-keyframe global map with a world voxel occupancy set (see global_map.hpp).
#include "dloam/core/global_map.hpp"

#include <tsl/robin_map.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {
constexpr double kKeyRange = 2.0e9;  // voxels per axis each side of 0 (32-bit keys)

std::uint32_t axis_key(double x, double leaf) {
  const double v = std::floor(x / leaf);
  if (!(std::abs(v) < kKeyRange))
    throw InputError("global map: point at " + std::to_string(x) + " m is outside the map's range (" +
                     std::to_string(kKeyRange * leaf / 1000.0) + " km at map_leaf_size " +
                     std::to_string(leaf) + " m)");
  return static_cast<std::uint32_t>(static_cast<std::int64_t>(v) + 0x80000000LL);  // offset: no sign
}

using BlockKey = std::array<std::uint32_t, 3>;

struct BlockHash {
  std::size_t operator()(const BlockKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k[0]) << 32 | k[1];
    h ^= static_cast<std::uint64_t>(k[2]) * 0x9E3779B97F4A7C15ULL;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    return static_cast<std::size_t>(h);
  }
};
}  // namespace

// Voxels in blocks of 8 x 8 x 8, a bit each: a map's points lie on surfaces, so a block holds tens
// of them and the blocks of a region fit in the cache. A rebuild after a loop closure inserts
// millions of points; a hash set of single voxels spends most of that time in cache misses.
struct GlobalMap::Occupancy {
  tsl::robin_map<BlockKey, std::uint32_t, BlockHash> index;  // block -> its bits
  std::vector<std::array<std::uint64_t, 8>> bits;

  /// Marks the voxel of a world point occupied; false when it already was.
  bool occupy(const Vec3& world, double leaf) {
    if (leaf <= 0.0) return true;
    const std::uint32_t x = axis_key(world.x(), leaf), y = axis_key(world.y(), leaf),
                        z = axis_key(world.z(), leaf);
    const auto [it, fresh] =
        index.try_emplace(BlockKey{x >> 3, y >> 3, z >> 3}, static_cast<std::uint32_t>(bits.size()));
    if (fresh) bits.push_back({});
    const unsigned bit = (x & 7u) | (y & 7u) << 3 | (z & 7u) << 6;
    std::uint64_t& word = bits[it->second][bit >> 6];
    const std::uint64_t mask = std::uint64_t{1} << (bit & 63u);
    if (word & mask) return false;
    word |= mask;
    return true;
  }
  void occupy(const Points& points, const Pose& pose, double leaf) {
    for (const Eigen::Vector3f& p : points) occupy(pose * p.cast<double>(), leaf);
  }
};

GlobalMap::GlobalMap(double leaf) : leaf_(leaf), occupied_(std::make_shared<Occupancy>()) {}

void GlobalMap::add(std::size_t keyframe, const std::vector<Vec3>& points, const Pose& pose) {
  if (local_.size() <= keyframe) {
    local_.resize(keyframe + 1);
    placed_.resize(keyframe + 1, Pose::Identity());
    reach_.resize(keyframe + 1, 0.0F);
  }
  placed_[keyframe] = pose;
  auto& kept = local_[keyframe];
  if (!kept) {
    kept = std::make_shared<Points>();
  } else if (kept.use_count() > 1) {  // a snapshot holds it: copy on write
    kept = std::make_shared<Points>(*kept);
  }
  float& reach = reach_[keyframe];
  for (const Vec3& p : points)
    if (occupied_->occupy(pose * p, leaf_)) {
      kept->push_back(p.cast<float>());
      reach = std::max(reach, kept->back().norm());
    }
}

void GlobalMap::move(const std::vector<Pose>& keyframe_poses) {
  adopt(rebuild(snapshot(), keyframe_poses, leaf_), keyframe_poses);
}

GlobalMap::Snapshot GlobalMap::snapshot() const { return {{local_.begin(), local_.end()}, placed_, reach_}; }

GlobalMap::Rebuilt GlobalMap::rebuild(const Snapshot& snapshot, const std::vector<Pose>& keyframe_poses,
                                      double leaf) {
  Rebuilt out;
  const std::size_t n = std::min(snapshot.points.size(), keyframe_poses.size());
  // How far a keyframe's farthest point moves: |dt| + reach * angle, with 2 sin(angle / 2) <= angle.
  bool moved = false;
  for (std::size_t k = 0; k < n && !moved; ++k) {
    const Pose& a = snapshot.placed[k];
    const Pose& b = keyframe_poses[k];
    const double angle = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
    moved = (b.translation() - a.translation()).norm() + snapshot.reach[k] * angle >= 0.5 * leaf;
  }
  if (!moved) return out;
  out.occupancy = std::make_shared<Occupancy>();
  for (; out.keyframes < n; ++out.keyframes)
    if (const auto& points = snapshot.points[out.keyframes])
      out.occupancy->occupy(*points, keyframe_poses[out.keyframes], leaf);
  return out;
}

void GlobalMap::adopt(Rebuilt rebuilt, const std::vector<Pose>& keyframe_poses) {
  if (!rebuilt.occupancy) return;
  occupied_ = std::move(rebuilt.occupancy);
  for (std::size_t k = 0; k < rebuilt.keyframes; ++k) placed_[k] = keyframe_poses[k];
  // The newest keyframe of the snapshot may have grown since: all of its points again (a voxel
  // already held is not added twice), and every later keyframe.
  const std::size_t from = rebuilt.keyframes > 0 ? rebuilt.keyframes - 1 : 0;
  for (std::size_t k = from; k < local_.size() && k < keyframe_poses.size(); ++k)
    if (local_[k]) {
      occupied_->occupy(*local_[k], keyframe_poses[k], leaf_);
      placed_[k] = keyframe_poses[k];
    }
}

std::vector<Vec3> GlobalMap::points(const std::vector<Pose>& keyframe_poses) const {
  std::vector<Vec3> world;
  world.reserve(size());
  for (std::size_t k = 0; k < local_.size() && k < keyframe_poses.size(); ++k)
    if (local_[k])
      for (const Eigen::Vector3f& p : *local_[k]) world.push_back(keyframe_poses[k] * p.cast<double>());
  return voxel_downsample_points(world, leaf_);
}

std::size_t GlobalMap::size() const {
  std::size_t n = 0;
  for (const auto& v : local_) n += v ? v->size() : 0;
  return n;
}

}  // namespace dloam
