// The local map kept up to date keyframe by keyframe: it holds a point in every voxel the members'
// features occupy, stays bounded as keyframes leave, is rebuilt seldom, and equals a downsampling
// of the members at once after the keyframes move.
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "dloam/core/local_map.hpp"
#include "dloam/core/voxel_grid.hpp"

using namespace dloam;

namespace {
constexpr double kRadius = 10.0, kEdgeLeaf = 0.2, kPlaneLeaf = 0.4;

Pose at(double x) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(x, 0.0, 0.0);
  return T;
}

/// A keyframe at x: a pole 1 m ahead (edges) and a 4 m stretch of wall 5 m to the left (planes),
/// in the sensor frame; points off the voxel boundaries.
Keyframe keyframe(std::size_t scan, double x) {
  Keyframe kf;
  kf.scan = scan;
  kf.pose = at(x);
  for (int k = 0; k < 40; ++k) kf.edges.emplace_back(1.03, 3.03, 0.05 * k + 0.013);
  for (int i = 0; i < 40; ++i)
    for (int k = 0; k < 20; ++k) kf.planes.emplace_back(-2.0 + 0.1 * i + 0.017, 5.03, 0.1 * k + 0.021);
  return kf;
}

/// World features of the given keyframes, downsampled at once.
std::vector<Vec3> at_once(const std::vector<Keyframe>& kfs, const std::vector<std::size_t>& members,
                          bool edges, double leaf) {
  std::vector<Vec3> world;
  for (std::size_t i : members)
    for (const Vec3& p : edges ? kfs[i].edges : kfs[i].planes) world.push_back(kfs[i].pose * p);
  return voxel_downsample_points(world, leaf);
}

std::set<std::tuple<int, int, int>> voxels(const std::vector<Vec3>& pts, double leaf) {
  std::set<std::tuple<int, int, int>> out;
  for (const Vec3& p : pts) {
    VoxelIndex::Key key;
    EXPECT_TRUE(VoxelIndex::key_of(p / leaf, key));
    out.emplace(key.x, key.y, key.z);
  }
  return out;
}

/// Members as LocalMap::around defines them: within the radius, or among the last 10.
std::vector<std::size_t> members_at(const std::vector<Keyframe>& kfs, const Vec3& position) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < kfs.size(); ++i)
    if (i + 10 >= kfs.size() || (kfs[i].pose.translation() - position).norm() < kRadius) out.push_back(i);
  return out;
}
}  // namespace

TEST(LocalMap, KeptUpToDateKeyframeByKeyframeAndRebuiltSeldom) {
  LocalMap map(kRadius, kEdgeLeaf, kPlaneLeaf);
  const std::size_t n = 60;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 1.5 * static_cast<double>(i);
    map.add(keyframe(i, x));
    const FeatureMap& m = map.around(Vec3(x, 0.0, 0.0));
    const auto members = members_at(map.keyframes(), Vec3(x, 0.0, 0.0));
    const auto edges = at_once(map.keyframes(), members, true, kEdgeLeaf);
    const auto planes = at_once(map.keyframes(), members, false, kPlaneLeaf);
    // Every voxel the members occupy holds a point of the map...
    const auto edge_voxels = voxels(m.edges.points(), kEdgeLeaf);
    const auto plane_voxels = voxels(m.planes.points(), kPlaneLeaf);
    for (const auto& v : voxels(edges, kEdgeLeaf)) ASSERT_TRUE(edge_voxels.count(v)) << "keyframe " << i;
    for (const auto& v : voxels(planes, kPlaneLeaf)) ASSERT_TRUE(plane_voxels.count(v)) << "keyframe " << i;
    // ...and keyframes that left add a bounded share: at most half the members' points again.
    EXPECT_LE(2 * m.planes.size(), 3 * planes.size()) << "keyframe " << i;
    EXPECT_LE(2 * m.edges.size(), 3 * edges.size() + 2) << "keyframe " << i;
  }
  // One rebuild per several keyframes, not one per keyframe.
  EXPECT_GE(map.rebuilds(), 2u);
  EXPECT_LE(map.rebuilds(), n / 4);

  // Keyframes moved (a loop closure): the map is the members' features downsampled at once.
  std::vector<Pose> moved;
  for (std::size_t i = 0; i < n; ++i) moved.push_back(at(1.5 * static_cast<double>(i) + 0.37));
  map.set_poses(moved);
  const Vec3 position(1.5 * static_cast<double>(n - 1), 0.0, 0.0);
  const std::size_t before = map.rebuilds();
  const FeatureMap& m = map.around(position);
  EXPECT_EQ(map.rebuilds(), before + 1);
  const auto members = members_at(map.keyframes(), position);
  EXPECT_EQ(m.edges.points(), at_once(map.keyframes(), members, true, kEdgeLeaf));
  EXPECT_EQ(m.planes.points(), at_once(map.keyframes(), members, false, kPlaneLeaf));
  // Asked again at the same place: the same map, not rebuilt.
  EXPECT_EQ(&map.around(position), &m);
  EXPECT_EQ(map.rebuilds(), before + 1);
}
