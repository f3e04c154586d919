// Voxel-grid downsampling keeping the point nearest each voxel's centre. Voxels live in a
// compact open-addressing hash table (16-byte slots, linear probing): std::unordered_map's
// per-node allocations, and fresh memory in general (page faults), cost more than the rest.
#include "dloam/core/voxel_grid.hpp"

#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>

namespace dloam {

namespace {

struct VoxelKey {
  std::int32_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

// floor(x) as an int32; false when x is not finite or out of range.
bool floor_int(double x, std::int32_t& out) {
  if (!(std::abs(x) < 2.0e9)) return false;
  const auto t = static_cast<std::int64_t>(x);
  out = static_cast<std::int32_t>(t - (x < static_cast<double>(t)));
  return true;
}

struct Voxel {
  int best = -1;  // index into ids of the point nearest the voxel's centre so far
  double best_d2 = 0.0;
};

// Maps voxel keys to indices into `voxels`; doubles when half full.
class VoxelTable {
 public:
  explicit VoxelTable(std::size_t expected) {
    std::size_t cap = 64;
    while (cap < 2 * expected) cap *= 2;
    slot_.assign(cap, Slot{});
  }
  /// Index of the voxel with this key in `voxels`, appended when new.
  int find_or_add(const VoxelKey& key, std::vector<Voxel>& voxels) {
    std::size_t h = hash(key);
    for (;; h = (h + 1) & (slot_.size() - 1)) {
      if (slot_[h].voxel < 0) break;
      if (slot_[h].key == key) return slot_[h].voxel;
    }
    const int v = static_cast<int>(voxels.size());
    slot_[h] = Slot{key, v};
    voxels.emplace_back();
    if (2 * voxels.size() > slot_.size()) grow();
    return v;
  }

 private:
  struct Slot {
    VoxelKey key;
    int voxel = -1;
  };
  [[nodiscard]] std::size_t hash(const VoxelKey& k) const {
    const std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) * 73856093ULL ^
                            static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) * 19349669ULL ^
                            static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z)) * 83492791ULL;
    return static_cast<std::size_t>((h ^ (h >> 29)) * 0x9E3779B97F4A7C15ULL >> 20) & (slot_.size() - 1);
  }
  void grow() {
    std::vector<Slot> old(2 * slot_.size());
    old.swap(slot_);
    for (const Slot& s : old) {
      if (s.voxel < 0) continue;
      std::size_t h = hash(s.key);
      while (slot_[h].voxel >= 0) h = (h + 1) & (slot_.size() - 1);
      slot_[h] = s;
    }
  }
  std::vector<Slot> slot_;
};

}  // namespace

std::vector<int> voxel_downsample(const std::vector<Vec3>& points, double leaf,
                                  const std::vector<int>* subset) {
  std::vector<int> ids;
  if (subset) {
    ids = *subset;
  } else {
    ids.resize(points.size());
    std::iota(ids.begin(), ids.end(), 0);
  }
  if (!(leaf > 0.0)) return ids;
  const double inv = 1.0 / leaf;
  std::vector<Voxel> voxels;
  voxels.reserve(ids.size() / 4);
  VoxelTable table(ids.size() / 4);
  VoxelKey last_key;
  int last = -1;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Vec3 scaled = points[static_cast<std::size_t>(ids[k])] * inv;
    VoxelKey key;
    if (!floor_int(scaled.x(), key.x) || !floor_int(scaled.y(), key.y) || !floor_int(scaled.z(), key.z))
      throw InputError("voxel_downsample: point " + std::to_string(ids[k]) +
                       " is not finite or too far out for a voxel of " + std::to_string(leaf) + " m");
    // Consecutive points (e.g. along a scan row) often share a voxel: skip the lookup then.
    if (last < 0 || !(key == last_key)) last = table.find_or_add(key, voxels), last_key = key;
    Voxel& vox = voxels[static_cast<std::size_t>(last)];
    const Vec3 centre(key.x + 0.5, key.y + 0.5, key.z + 0.5);
    const double d2 = (scaled - centre).squaredNorm();
    if (vox.best < 0 || d2 < vox.best_d2) vox.best = static_cast<int>(k), vox.best_d2 = d2;
  }
  std::vector<int> kept;
  kept.reserve(voxels.size());
  for (const Voxel& vox : voxels) kept.push_back(ids[static_cast<std::size_t>(vox.best)]);
  return kept;
}

std::vector<Vec3> voxel_downsample_points(const std::vector<Vec3>& points, double leaf) {
  std::vector<Vec3> out;
  const auto kept = voxel_downsample(points, leaf);
  out.reserve(kept.size());
  for (int i : kept) out.push_back(points[static_cast<std::size_t>(i)]);
  return out;
}

}  // namespace dloam
