// The global map of static points (map.ply, paper III.G), kept per keyframe: each point is stored
// in the sensor frame of the keyframe that added it, so a loop closure that moves the keyframes
// moves their points with them. A world voxel grid of size `leaf` decides which points are new:
// a voxel is owned by the first keyframe that filled it, so memory grows with the mapped area,
// not with the length of the drive.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

class GlobalMap {
 public:
  explicit GlobalMap(double leaf) : leaf_(leaf) {}

  /// Adds the points (sensor frame) of keyframe `keyframe` at world pose `pose`; points falling
  /// in an occupied voxel are dropped. Keyframes are added in increasing order (a keyframe's points
  /// may come in several calls).
  /// Throws InputError on a point more than 2e9 voxels (400,000 km at 0.2 m) from the origin.
  void add(std::size_t keyframe, const std::vector<Vec3>& points, const Pose& pose);
  /// The keyframes moved (loop closure): the occupancy is rebuilt at their new poses.
  void move(const std::vector<Pose>& keyframe_poses);
  /// World points with every keyframe at `keyframe_poses`, downsampled to one per voxel.
  [[nodiscard]] std::vector<Vec3> points(const std::vector<Pose>& keyframe_poses) const;
  /// Points stored (before the final downsampling).
  [[nodiscard]] std::size_t size() const;

 private:
  /// Marks the voxel of a world point occupied; false when it already was.
  bool occupy(const Vec3& world);

  using Key = std::array<std::int32_t, 3>;  ///< voxel indices
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  double leaf_;
  std::vector<std::vector<Eigen::Vector3f>> local_;  ///< per keyframe, sensor frame
  std::unordered_set<Key, KeyHash> occupied_;
};

}  // namespace dloam
