// Voxel-grid downsampling that keeps real input points: one representative per occupied voxel
// (the point nearest the voxel's centre), so callers keep each point's index.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

/// Indices into `points` (or into `subset` when given: then only those points are considered
/// and the returned values are elements of `subset`) of one point per voxel of size `leaf`,
/// in the order voxels are first met. `leaf <= 0` keeps every point. Deterministic.
/// Throws InputError on a non-finite point or one more than 2e9 voxels from the origin.
std::vector<int> voxel_downsample(const std::vector<Vec3>& points, double leaf,
                                  const std::vector<int>* subset = nullptr);

/// The points themselves, downsampled as above.
std::vector<Vec3> voxel_downsample_points(const std::vector<Vec3>& points, double leaf);

/// Voxel keys to dense indices 0, 1, 2, ... in the order keys are first met (open addressing,
/// linear probing, at most half full): std::unordered_map's per-node allocations, and fresh memory
/// in general (page faults), cost more than the rest of a downsampling.
class VoxelIndex {
 public:
  struct Key {
    std::int32_t x = 0, y = 0, z = 0;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  explicit VoxelIndex(std::size_t expected = 0);
  /// The key of the voxel of size 1 holding `scaled` (a point divided by the leaf size); false
  /// when a coordinate is not finite or more than 2e9 voxels from the origin.
  static bool key_of(const Vec3& scaled, Key& key);
  /// The index of `key`; a new key gets the index size() (then size() grows by one).
  int find_or_add(const Key& key);
  [[nodiscard]] std::size_t size() const { return size_; }
  void clear();

 private:
  struct Slot {
    Key key;
    int voxel = -1;
  };
  [[nodiscard]] std::size_t slot_of(const Key& key) const;
  void grow();
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

/// The same downsampling built up set by set: after any sequence of add() calls, points() holds,
/// for each voxel met, the point added to it that lies nearest its centre, i.e. the points of
/// voxel_downsample_points over the union of the sets (in the order voxels were first met).
class VoxelPoints {
 public:
  explicit VoxelPoints(double leaf) : leaf_(leaf) {}
  /// Throws InputError on a non-finite point or one more than 2e9 voxels from the origin.
  void add(const std::vector<Vec3>& points);
  void clear();
  [[nodiscard]] const std::vector<Vec3>& points() const { return points_; }

 private:
  double leaf_;
  VoxelIndex index_;
  std::vector<Vec3> points_;  ///< per voxel: the point nearest its centre so far
  std::vector<double> d2_;    ///< per voxel: its squared distance to the centre, in leaves
};

}  // namespace dloam
