// Global map per keyframe: one point per world voxel, points move with their keyframe when a loop
// closure corrects the keyframe poses, and the occupancy follows the moved points.
#include <gtest/gtest.h>

#include "dloam/core/global_map.hpp"

using namespace dloam;

namespace {
Pose translation(double x, double y) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(x, y, 0.0);
  return T;
}

/// A 4 m x 4 m wall of points every 5 cm in the sensor's x = 5.1 plane (off the voxel boundaries:
/// points are stored as floats).
std::vector<Vec3> wall() {
  std::vector<Vec3> pts;
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 80; ++j) pts.emplace_back(5.1, -2.0 + 0.05 * i + 0.0123, 0.05 * j + 0.0123);
  return pts;
}
}  // namespace

TEST(GlobalMap, OneVoxelOwnerAndPointsMoveWithTheirKeyframe) {
  GlobalMap map(0.2);
  const std::vector<Vec3> pts = wall();
  map.add(0, pts, translation(0, 0));
  const std::size_t first = map.size();
  EXPECT_NEAR(static_cast<double>(first), 20.0 * 20.0, 40.0);  // ~one point per 0.2 m voxel of the wall
  map.add(1, pts, translation(0, 0));                          // the same wall again: nothing new
  EXPECT_EQ(map.size(), first);
  map.add(2, pts, translation(0, 4.0));  // the wall continued 4 m to the left: all new
  EXPECT_NEAR(static_cast<double>(map.size()), 2.0 * first, 40.0);

  // A loop closure says keyframe 2 was 1 m further along x: its points (only) move by 1 m.
  const std::vector<Pose> corrected = {translation(0, 0), translation(0, 0), translation(1.0, 4.0)};
  const std::vector<Vec3> out = map.points(corrected);
  std::size_t at5 = 0, at6 = 0;
  for (const Vec3& p : out) {
    if (std::abs(p.x() - 5.1) < 1e-6) ++at5;
    if (std::abs(p.x() - 6.1) < 1e-6) {
      ++at6;
      EXPECT_GE(p.y(), 2.0 - 1e-9);
    }
  }
  EXPECT_NEAR(static_cast<double>(at5), static_cast<double>(first), 40.0);
  EXPECT_EQ(at5 + at6, out.size());
  EXPECT_GT(at6, 300u);

  // After move(), the old place of keyframe 2's wall is free again and the new place is occupied.
  map.move(corrected);
  const std::size_t before = map.size();
  map.add(3, pts, translation(0, 4.0));
  EXPECT_NEAR(static_cast<double>(map.size() - before), static_cast<double>(first), 40.0);
  map.add(4, pts, translation(1.0, 4.0));
  EXPECT_LT(map.size() - before, first + 40);
}

TEST(GlobalMap, RejectsPointsOutsideItsRange) {
  // 32-bit voxel keys: +-2e9 voxels, 400,000 km at 0.2 m, 2,000 km at the smallest leaf (1 mm).
  GlobalMap map(0.2);
  EXPECT_NO_THROW(map.add(0, {Vec3(1e6, -1e6, 1e6)}, Pose::Identity()));
  EXPECT_EQ(map.size(), 1u);
  EXPECT_THROW(map.add(1, {Vec3(1e9, 0, 0)}, Pose::Identity()), InputError);
  GlobalMap fine(0.001);
  EXPECT_NO_THROW(fine.add(0, {Vec3(1.5e6, 0, 0)}, Pose::Identity()));
  EXPECT_THROW(fine.add(1, {Vec3(2.5e6, 0, 0)}, Pose::Identity()), InputError);
}

TEST(GlobalMap, ARebuildBesideTheScansEqualsAMoveAndSnapshotsStayAsTaken) {
  const std::vector<Vec3> pts = wall();
  GlobalMap now(0.2), beside(0.2);
  for (GlobalMap* map : {&now, &beside}) {
    map->add(0, pts, translation(0, 0));
    map->add(1, pts, translation(0, 4.0));
  }
  const GlobalMap::Snapshot snapshot = beside.snapshot();
  const std::size_t held = snapshot.points[1]->size();
  // After the snapshot: keyframe 1 grows (the wall 2 m further on) and keyframe 2 comes.
  for (GlobalMap* map : {&now, &beside}) {
    map->add(1, pts, translation(0, 6.0));
    map->add(2, pts, translation(0, 8.0));
  }
  EXPECT_EQ(snapshot.points[1]->size(), held);  // copied on write, not changed under the snapshot
  EXPECT_GT(beside.size(), now.size() / 2);

  const std::vector<Pose> corrected = {translation(0, 0), translation(1.0, 4.0), translation(1.0, 8.0)};
  now.move(corrected);
  const GlobalMap::Rebuilt rebuilt = GlobalMap::rebuild(snapshot, corrected, 0.2);
  EXPECT_EQ(rebuilt.keyframes, 2u);
  beside.adopt(rebuilt, corrected);
  // The same occupancy: a wall at every old and new place adds the same points to both maps.
  for (double y : {0.0, 4.0, 6.0, 8.0, 12.0})
    for (double x : {0.0, 1.0}) {
      const std::size_t n0 = now.size(), n1 = beside.size();
      now.add(3, pts, translation(x, y));
      beside.add(3, pts, translation(x, y));
      EXPECT_EQ(now.size() - n0, beside.size() - n1) << x << " " << y;
    }
  const std::vector<Pose> all = {corrected[0], corrected[1], corrected[2], Pose::Identity()};
  EXPECT_EQ(now.points(all).size(), beside.points(all).size());
}

TEST(GlobalMap, AMoveOfLessThanHalfAVoxelKeepsTheOccupancy) {
  const std::vector<Vec3> pts = wall();  // farthest point 6.8 m from its keyframe
  GlobalMap map(0.2);
  map.add(0, pts, translation(0, 0));
  map.add(1, pts, translation(0, 4.0));
  // Keyframe 1 moved by 3 cm and turned by 0.5 deg (6 cm at 6.8 m): no point moves by 0.1 m.
  const auto moved = [](double x, double deg) {
    Pose T = translation(x, 4.0);
    T.linear() = Eigen::AngleAxisd(deg * M_PI / 180.0, Vec3::UnitZ()).toRotationMatrix();
    return T;
  };
  const std::vector<Pose> small = {translation(0, 0), moved(0.03, 0.5)};
  const GlobalMap::Rebuilt kept = GlobalMap::rebuild(map.snapshot(), small, 0.2);
  EXPECT_FALSE(kept.occupancy);
  map.adopt(kept, small);
  const std::size_t n = map.size();
  map.add(2, pts, translation(0, 4.0));  // the voxels of keyframe 1's first place are still held
  EXPECT_EQ(map.size(), n);
  // Keyframe 0 by 12 cm: rebuilt.
  EXPECT_TRUE(GlobalMap::rebuild(map.snapshot(), {translation(0.12, 0), small[1], translation(0, 4.0)}, 0.2)
                  .occupancy);
  // Small moves add up against the pose the voxels were set at: another 3 cm and 0.5 deg on top of
  // the first is rebuilt.
  EXPECT_TRUE(
      GlobalMap::rebuild(map.snapshot(), {translation(0, 0), moved(0.06, 1.0), translation(0, 4.0)}, 0.2)
          .occupancy);
  // After a rebuild the voxels are set at the new poses.
  const std::vector<Pose> twice = {translation(0, 0), moved(0.06, 1.0), translation(0, 4.0)};
  map.adopt(GlobalMap::rebuild(map.snapshot(), twice, 0.2), twice);
  EXPECT_FALSE(GlobalMap::rebuild(map.snapshot(), twice, 0.2).occupancy);
}
