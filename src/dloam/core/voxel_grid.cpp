// Voxel-grid downsampling keeping the point nearest each voxel's centre.
#include "dloam/core/voxel_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace dloam {

namespace {

// floor(x) as an int32; false when x is not finite or out of range.
bool floor_int(double x, std::int32_t& out) {
  if (!(std::abs(x) < 2.0e9)) return false;
  const auto t = static_cast<std::int64_t>(x);
  out = static_cast<std::int32_t>(t - (x < static_cast<double>(t)));
  return true;
}

double to_centre_sq(const Vec3& scaled, const VoxelIndex::Key& key) {
  return (scaled - Vec3(key.x + 0.5, key.y + 0.5, key.z + 0.5)).squaredNorm();
}

InputError far_point(std::size_t i, double leaf) {
  return InputError("voxel_downsample: point " + std::to_string(i) +
                    " is not finite or too far out for a voxel of " + std::to_string(leaf) + " m");
}

}  // namespace

VoxelIndex::VoxelIndex(std::size_t expected) {
  std::size_t cap = 64;
  while (cap < 2 * expected) cap *= 2;
  slots_.assign(cap, Slot{});
}

bool VoxelIndex::key_of(const Vec3& scaled, Key& key) {
  return floor_int(scaled.x(), key.x) && floor_int(scaled.y(), key.y) && floor_int(scaled.z(), key.z);
}

int VoxelIndex::find_or_add(const Key& key) {
  std::size_t h = slot_of(key);
  for (;; h = (h + 1) & (slots_.size() - 1)) {
    if (slots_[h].voxel < 0) break;
    if (slots_[h].key == key) return slots_[h].voxel;
  }
  const int v = static_cast<int>(size_++);
  slots_[h] = Slot{key, v};
  if (2 * size_ > slots_.size()) grow();
  return v;
}

void VoxelIndex::clear() {
  std::fill(slots_.begin(), slots_.end(), Slot{});
  size_ = 0;
}

std::size_t VoxelIndex::slot_of(const Key& k) const {
  const std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) * 73856093ULL ^
                          static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) * 19349669ULL ^
                          static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z)) * 83492791ULL;
  return static_cast<std::size_t>((h ^ (h >> 29)) * 0x9E3779B97F4A7C15ULL >> 20) & (slots_.size() - 1);
}

void VoxelIndex::grow() {
  std::vector<Slot> old(2 * slots_.size());
  old.swap(slots_);
  for (const Slot& s : old) {
    if (s.voxel < 0) continue;
    std::size_t h = slot_of(s.key);
    while (slots_[h].voxel >= 0) h = (h + 1) & (slots_.size() - 1);
    slots_[h] = s;
  }
}

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
  struct Voxel {
    int best = -1;  // index into ids of the point nearest the voxel's centre so far
    double best_d2 = 0.0;
  };
  std::vector<Voxel> voxels;
  voxels.reserve(ids.size() / 4);
  VoxelIndex index(ids.size() / 4);
  VoxelIndex::Key last_key;
  int last = -1;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Vec3 scaled = points[static_cast<std::size_t>(ids[k])] * inv;
    VoxelIndex::Key key;
    if (!VoxelIndex::key_of(scaled, key)) throw far_point(static_cast<std::size_t>(ids[k]), leaf);
    // Consecutive points (e.g. along a scan row) often share a voxel: skip the lookup then.
    if (last < 0 || !(key == last_key)) {
      last = index.find_or_add(key), last_key = key;
      if (static_cast<std::size_t>(last) == voxels.size()) voxels.emplace_back();
    }
    Voxel& vox = voxels[static_cast<std::size_t>(last)];
    const double d2 = to_centre_sq(scaled, key);
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

void VoxelPoints::add(const std::vector<Vec3>& points) {
  if (!(leaf_ > 0.0)) {
    points_.insert(points_.end(), points.begin(), points.end());
    return;
  }
  const double inv = 1.0 / leaf_;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 scaled = points[i] * inv;
    VoxelIndex::Key key;
    if (!VoxelIndex::key_of(scaled, key)) throw far_point(i, leaf_);
    const auto v = static_cast<std::size_t>(index_.find_or_add(key));
    const double d2 = to_centre_sq(scaled, key);
    if (v == points_.size()) {
      points_.push_back(points[i]);
      d2_.push_back(d2);
    } else if (d2 < d2_[v]) {
      points_[v] = points[i];
      d2_[v] = d2;
    }
  }
}

void VoxelPoints::clear() {
  index_.clear();
  points_.clear();
  d2_.clear();
}

}  // namespace dloam
