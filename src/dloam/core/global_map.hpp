// The global map of static points (map.ply, paper III.G), kept per keyframe: each point is stored
// in the sensor frame of the keyframe that added it, so a loop closure that moves the keyframes
// moves their points with them. A world voxel grid of size `leaf` decides which points are new:
// a point is kept only when its voxel holds no point yet, so memory grows with the mapped area,
// not with the length of the drive.
//
// After a loop closure the voxel occupancy is rebuilt at the corrected poses, unless no stored point
// moved by half a voxel or more from where it was placed in the occupancy (a loop closure revisited
// often moves the keyframes by millimetres). The rebuild can run off the scan path: snapshot()
// shares the stored points (read-only; a keyframe that grows while a snapshot holds it is copied
// first), rebuild() runs on any thread, adopt() takes the result.
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

class GlobalMap {
 public:
  using Points = std::vector<Eigen::Vector3f>;
  /// The stored points of every keyframe at one moment, shared read-only, with the pose each
  /// keyframe's points hold their voxels at and the range of its farthest point.
  struct Snapshot {
    std::vector<std::shared_ptr<const Points>> points;
    std::vector<Pose> placed;
    std::vector<float> reach;
  };
  struct Occupancy;  ///< the voxels holding a point (defined in global_map.cpp)
  /// An occupancy built from a snapshot, and how many keyframes it covers. No occupancy: no point
  /// of the snapshot moved by half a voxel, the current one stays.
  struct Rebuilt {
    std::shared_ptr<Occupancy> occupancy;
    std::size_t keyframes = 0;
  };

  explicit GlobalMap(double leaf);

  /// Adds the points (sensor frame) of keyframe `keyframe` at world pose `pose`; points falling
  /// in an occupied voxel are dropped. Keyframes are added in increasing order (a keyframe's points
  /// may come in several calls).
  /// Throws InputError on a point more than 2e9 voxels (400,000 km at 0.2 m) from the origin.
  void add(std::size_t keyframe, const std::vector<Vec3>& points, const Pose& pose);
  /// The keyframes moved (loop closure): rebuild() and adopt() at once, on this thread.
  void move(const std::vector<Pose>& keyframe_poses);
  /// The stored points now, for rebuild() on another thread.
  [[nodiscard]] Snapshot snapshot() const;
  /// The occupancy of a snapshot's points with keyframe k at `keyframe_poses[k]`, or none when no
  /// point moves by half a voxel from where it holds its voxel. Touches nothing but its arguments:
  /// safe on any thread.
  [[nodiscard]] static Rebuilt rebuild(const Snapshot& snapshot, const std::vector<Pose>& keyframe_poses,
                                       double leaf);
  /// Replaces the occupancy with a rebuilt one, then adds to it every point the snapshot did not
  /// hold (keyframes added or grown since), with keyframe k at `keyframe_poses[k]`. A Rebuilt
  /// without occupancy changes nothing.
  void adopt(Rebuilt rebuilt, const std::vector<Pose>& keyframe_poses);
  /// World points with every keyframe at `keyframe_poses`, downsampled to one per voxel.
  [[nodiscard]] std::vector<Vec3> points(const std::vector<Pose>& keyframe_poses) const;
  /// Points stored (before the final downsampling).
  [[nodiscard]] std::size_t size() const;

 private:
  double leaf_;
  std::vector<std::shared_ptr<Points>> local_;  ///< per keyframe, sensor frame
  std::vector<Pose> placed_;                    ///< per keyframe: the pose its voxels were set at
  std::vector<float> reach_;                    ///< per keyframe: range of its farthest point (m)
  std::shared_ptr<Occupancy> occupied_;
};

}  // namespace dloam
