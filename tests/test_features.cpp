// Feature extraction (paper III.E, eq. 14): smoothness, LOAM's occlusion / parallel rules, edge
// and plane selection per sub-image, dynamic masks and double quotas, voxel downsampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>
#include <tuple>

#include "dloam/core/features.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/smoothness.hpp"
#include "dloam/core/voxel_grid.hpp"
#include "dloam/io/kitti.hpp"
#include "seg_test_scene.hpp"

using namespace dloam;
using dloam::test::Scene;

namespace {

struct Fixture {
  Scene scene = test::make_scene();
  SegmentationResult seg = segment(scene.points, scene.sensor, SegmentationConfig{});
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// Horizontal distance from p to the nearest vertical edge of the building block.
double to_building_edge(const Scene& s, const Vec3& p) {
  double best = 1e9;
  for (double x : {s.building.lo.x(), s.building.hi.x()})
    for (double y : {s.building.lo.y(), s.building.hi.y()})
      best = std::min(best, std::hypot(p.x() - x, p.y() - y));
  return best;
}

// A one-row segmented image with the given ranges (every pixel a cluster pixel), for smoothness.
SegmentationResult one_row(const std::vector<float>& ranges) {
  SegmentationResult seg;
  seg.image.rows = 1;
  seg.image.cols = static_cast<int>(ranges.size());
  seg.image.range = ranges;
  for (int u = 0; u < seg.image.cols; ++u) seg.image.point_of_pixel.push_back(u);
  seg.pixel_label.assign(ranges.size(), 1);
  return seg;
}

}  // namespace

TEST(Smoothness, Eq14OnAStepAndOcclusionMarksTheFarSide) {
  std::vector<float> r(40, 10.0f);
  for (int u = 20; u < 40; ++u) r[static_cast<std::size_t>(u)] = 12.0f;
  const RowSequences q = compute_smoothness(one_row(r), 10);
  ASSERT_EQ(q.size(), 40u);
  EXPECT_NEAR(q.c[10], 0.0, 1e-6);                    // flat: c = 0
  EXPECT_NEAR(q.c[17], 3 * 2.0 / (10 * 10.0), 1e-6);  // 3 of 10 neighbours 2 m farther
  EXPECT_NEAR(q.c[19], 5 * 2.0 / (10 * 10.0), 1e-6);
  EXPECT_NEAR(q.c[20], 5 * 2.0 / (10 * 12.0), 1e-6);
  // 2 m jump between columns 19 and 20: the far side (20..25) is occluded, the near side kept.
  EXPECT_TRUE(q.usable[19]);
  for (int u = 20; u <= 25; ++u) EXPECT_FALSE(q.usable[static_cast<std::size_t>(u)]) << u;
  EXPECT_TRUE(q.usable[27]);
}

TEST(Smoothness, BeamsNearlyParallelToTheSurfaceAreUnusable) {
  std::vector<float> r;
  for (int u = 0; u < 40; ++u) r.push_back(u < 20 ? 10.0f : 10.0f + 0.25f * static_cast<float>(u - 19));
  const RowSequences q = compute_smoothness(one_row(r), 10);
  EXPECT_TRUE(q.usable[10]);
  EXPECT_FALSE(q.usable[25]);  // 0.25 m per column at ~11.5 m: > 2 % on both sides
  const RowSequences short_row = compute_smoothness(one_row(std::vector<float>(8, 5.0f)), 10);
  for (std::size_t k = 0; k < short_row.size(); ++k) EXPECT_FALSE(short_row.usable[k]);
}

TEST(Smoothness, EmptySpaceCountsAsADepthJumpAndStopsTheRules) {
  // 20 columns of a wall, 20 empty (sky), 20 of a wall: the walls' last points before the sky are
  // silhouettes (each neighbour beyond the gap counts as 2 r_i), their interiors are flat.
  SegmentationResult seg = one_row(std::vector<float>(60, 10.0f));
  for (int u = 20; u < 40; ++u) seg.pixel_label[static_cast<std::size_t>(u)] = kOutlierLabel;
  for (int u = 40; u < 60; ++u) seg.image.range[static_cast<std::size_t>(u)] = 30.0f;  // far wall
  const RowSequences q = compute_smoothness(seg, 10);
  ASSERT_EQ(q.size(), 40u);
  EXPECT_NEAR(q.c[19], 5 * 10.0 / (10 * 10.0), 1e-6);  // col 19: 5 neighbours beyond the gap
  EXPECT_NEAR(q.c[17], 3 * 10.0 / (10 * 10.0), 1e-6);
  EXPECT_NEAR(q.c[10], 0.0, 1e-6);
  EXPECT_NEAR(q.c[20], 5 * 30.0 / (10 * 30.0), 1e-6);  // col 40, first after the gap
  // The 20 m jump at the wrap (col 59 -> col 0) occludes the far wall's end, not across the sky.
  EXPECT_FALSE(q.usable[39]);
  EXPECT_FALSE(q.usable[34]);
  EXPECT_TRUE(q.usable[20]);
  EXPECT_TRUE(q.usable[19]);
}

TEST(Features, EdgesOnThePoleAndTheBuildingCorner) {
  const Fixture& f = fixture();
  const Scene& s = f.scene;
  const FeatureSet fs = extract_features(s.points, f.seg, FeatureConfig{});
  ASSERT_EQ(fs.f_e.size(), fs.f_e_index.size());
  ASSERT_EQ(fs.F_e.size(), fs.F_e_index.size());
  const std::set<int> F_e(fs.F_e_index.begin(), fs.F_e_index.end());
  std::set<int> pole_rows, corner_rows;
  for (int i : fs.f_e_index) {
    EXPECT_TRUE(F_e.count(i)) << "f_e is a subset of F_e";
    if (s.hit[static_cast<std::size_t>(i)] == test::kPole)
      pole_rows.insert(s.row[static_cast<std::size_t>(i)]);
  }
  const Vec3 corner(s.building.lo.x(), s.building.hi.y(), 0.0);  // the vertical edge facing the sensor
  for (std::size_t n = 0; n < fs.F_e_index.size(); ++n) {
    const auto k = static_cast<std::size_t>(fs.F_e_index[n]);
    EXPECT_EQ(fs.F_e[n], s.points[k]);
    EXPECT_NE(s.hit[k], test::kGround) << "no edge on the ground";
    if (s.hit[k] == test::kBuilding) {
      // Edges of the block are its vertical edges (the corner and the two silhouettes), not its faces.
      EXPECT_LT(to_building_edge(s, s.points[k]), 0.5) << s.points[k].transpose();
      if (std::hypot(s.points[k].x() - corner.x(), s.points[k].y() - corner.y()) < 0.3)
        corner_rows.insert(s.row[k]);
    }
  }
  EXPECT_GE(pole_rows.size(), 5u) << "sharp edges along the pole";
  EXPECT_GE(corner_rows.size(), 5u) << "edges along the building's convex corner";
}

TEST(Features, PlanesAreFlatGroundAndSubsetsHold) {
  const Fixture& f = fixture();
  const Scene& s = f.scene;
  const FeatureConfig config;
  const FeatureSet fs = extract_features(s.points, f.seg, config);
  ASSERT_FALSE(fs.f_p.empty());
  const std::set<int> F_p(fs.F_p_index.begin(), fs.F_p_index.end());
  EXPECT_EQ(F_p.size(), fs.F_p_index.size()) << "no duplicates in F_p";
  for (int i : fs.f_p_index) {
    EXPECT_EQ(s.hit[static_cast<std::size_t>(i)], test::kGround);
    EXPECT_EQ(f.seg.point_label[static_cast<std::size_t>(i)], kGroundLabel);
    EXPECT_TRUE(F_p.count(i)) << "f_p is a subset of F_p";
  }
  // At most N_fp per sub-image row.
  EXPECT_LE(static_cast<int>(fs.f_p.size()), config.N_fp * config.N_div * s.sensor.N_scan);
  EXPECT_LE(static_cast<int>(fs.f_e.size()), config.N_fe * config.N_div * s.sensor.N_scan);
  ASSERT_EQ(fs.F_p_ground.size(), fs.F_p.size());
  int non_ground = 0;
  for (std::size_t k = 0; k < fs.F_p.size(); ++k) {
    const auto i = static_cast<std::size_t>(fs.F_p_index[k]);
    EXPECT_EQ(fs.F_p_ground[k] != 0, f.seg.point_label[i] == kGroundLabel);
    non_ground += !fs.F_p_ground[k];
  }
  EXPECT_GT(non_ground, 0) << "flat faces of the building are planes too";
  // Voxel-downsampled: far fewer planes than points.
  EXPECT_LT(fs.F_p.size(), s.points.size() / 2);
}

TEST(Features, MaskedDynamicPixelsGiveNoFeature) {
  const Fixture& f = fixture();
  const Scene& s = f.scene;
  FeatureMask mask;
  mask.excluded.assign(f.seg.image.range.size(), 0);
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (s.hit[i] == test::kPole || s.hit[i] == test::kBuilding)
      mask.excluded[static_cast<std::size_t>(f.seg.image.pixel_of_point(i))] = 1;
  const FeatureSet before = extract_features(s.points, f.seg, FeatureConfig{});
  const FeatureSet after = extract_features(s.points, f.seg, FeatureConfig{}, &mask);
  auto count_masked = [&](const std::vector<int>& idx) {
    return std::count_if(idx.begin(), idx.end(), [&](int i) {
      return mask.excluded[static_cast<std::size_t>(
                 f.seg.image.pixel_of_point(static_cast<std::size_t>(i)))] != 0;
    });
  };
  EXPECT_GT(count_masked(before.F_e_index), 0);
  EXPECT_GT(count_masked(before.F_p_index), 0);
  for (const auto* idx : {&after.f_e_index, &after.F_e_index, &after.f_p_index, &after.F_p_index})
    EXPECT_EQ(count_masked(*idx), 0);
  EXPECT_FALSE(after.F_e.empty()) << "the rest of the scene still gives edges";
}

TEST(Features, PseudoStaticSubImageGetsDoubleQuota) {
  const Fixture& f = fixture();
  const Scene& s = f.scene;
  FeatureConfig config;
  config.N_Fe = 2;  // make the quotas bind
  config.N_fp = 2;
  const int cols = f.seg.image.cols;
  // Flag one pixel of the building: its sub-image (column strip) gets double quotas.
  std::size_t b = 0;
  while (s.hit[b] != test::kBuilding) ++b;
  const int strip = s.col[b] * config.N_div / cols;
  FeatureMask mask;
  mask.pseudo_static.assign(f.seg.image.range.size(), 0);
  mask.pseudo_static[static_cast<std::size_t>(f.seg.image.pixel_of_point(b))] = 1;
  auto in_strip = [&](const std::vector<int>& idx, int which) {
    return std::count_if(idx.begin(), idx.end(), [&](int i) {
      return s.col[static_cast<std::size_t>(i)] * config.N_div / cols == which;
    });
  };
  const FeatureSet plain = extract_features(s.points, f.seg, config);
  const FeatureSet doubled = extract_features(s.points, f.seg, config, &mask);
  EXPECT_GT(in_strip(doubled.F_e_index, strip), in_strip(plain.F_e_index, strip));
  EXPECT_GT(in_strip(doubled.f_p_index, strip), in_strip(plain.f_p_index, strip));
  EXPECT_EQ(in_strip(doubled.f_p_index, strip), 2 * in_strip(plain.f_p_index, strip))
      << "ground is plentiful";
  const int other = (strip + 3) % config.N_div;
  EXPECT_EQ(in_strip(doubled.f_p_index, other), in_strip(plain.f_p_index, other));
  config.double_pseudo_static = false;
  const FeatureSet off = extract_features(s.points, f.seg, config, &mask);
  EXPECT_EQ(off.F_e_index, plain.F_e_index);
  EXPECT_EQ(off.f_p_index, plain.f_p_index);
}

TEST(Features, BadMaskThrowsInputError) {
  const Fixture& f = fixture();
  FeatureMask mask;
  mask.excluded.assign(10, 1);
  EXPECT_THROW(extract_features(f.scene.points, f.seg, FeatureConfig{}, &mask), InputError);
  std::vector<Vec3> fewer(f.scene.points.begin(), f.scene.points.end() - 1);
  EXPECT_THROW(extract_features(fewer, f.seg, FeatureConfig{}), InputError);
}

TEST(VoxelGrid, OnePointPerVoxelNearestItsCentre) {
  const std::vector<Vec3> pts = {{0.01, 0.01, 0.01},
                                 {0.08, 0.07, 0.06},
                                 {0.05, 0.05, 0.06},    // voxel (0,0,0)
                                 {0.15, 0.01, 0.01},    // voxel (1,0,0)
                                 {-0.01, 0.01, 0.01}};  // voxel (-1,0,0)
  EXPECT_EQ(voxel_downsample(pts, 0.1), (std::vector<int>{2, 3, 4}));
  const std::vector<int> subset = {0, 1, 3};
  EXPECT_EQ(voxel_downsample(pts, 0.1, &subset), (std::vector<int>{1, 3}));
  EXPECT_EQ(voxel_downsample(pts, 0.0).size(), pts.size());
  EXPECT_EQ(voxel_downsample_points(pts, 0.1), (std::vector<Vec3>{pts[2], pts[3], pts[4]}));
  std::vector<Vec3> bad = pts;
  bad[1].x() = std::nan("");
  EXPECT_THROW(voxel_downsample(bad, 0.1), InputError);
  bad[1].x() = 1e12;
  EXPECT_THROW(voxel_downsample(bad, 0.1), InputError);
}

TEST(VoxelGrid, PointsAddedSetBySetEqualOneDownsamplingOfTheirUnion) {
  // Three overlapping random clouds: one voxel of 0.3 m holds points of several clouds.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<std::vector<Vec3>> sets(3);
  for (auto& set : sets)
    for (int i = 0; i < 2000; ++i) set.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  VoxelPoints incremental(0.3);
  std::vector<Vec3> all;
  for (const auto& set : sets) {
    incremental.add(set);
    all.insert(all.end(), set.begin(), set.end());
  }
  EXPECT_EQ(incremental.points(), voxel_downsample_points(all, 0.3));
  incremental.clear();
  EXPECT_TRUE(incremental.points().empty());
  incremental.add(sets[1]);
  EXPECT_EQ(incremental.points(), voxel_downsample_points(sets[1], 0.3));
  std::vector<Vec3> bad = sets[0];
  bad[5].z() = std::nan("");
  EXPECT_THROW(incremental.add(bad), InputError);
}

TEST(VoxelGrid, LargeCloudKeepsOnePointPerOccupiedVoxel) {
  // A 20 x 20 x 4 m block of points every 15 cm: all 100 x 100 x 20 voxels of 0.2 m occupied.
  std::vector<Vec3> pts;
  for (int i = 0; i < 400; i += 3)
    for (int j = 0; j < 400; j += 3)
      for (int k = 0; k < 80; k += 3)
        pts.emplace_back(0.025 + 0.05 * i - 10.0, 0.025 + 0.05 * j - 10.0, 0.025 + 0.05 * k);
  const std::vector<int> kept = voxel_downsample(pts, 0.2);
  EXPECT_EQ(kept.size(), 100u * 100u * 20u);
  std::set<std::tuple<int, int, int>> voxels;
  for (int i : kept) {
    const Vec3& p = pts[static_cast<std::size_t>(i)];
    voxels.emplace(static_cast<int>(std::floor(p.x() / 0.2)), static_cast<int>(std::floor(p.y() / 0.2)),
                   static_cast<int>(std::floor(p.z() / 0.2)));
  }
  EXPECT_EQ(voxels.size(), kept.size()) << "one point per voxel";
}

// Real HDL-64E scan: counts within the quotas, edges off the ground, f_p on static ground.
TEST(FeaturesKitti, RealScanFeaturesAreSound) {
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir + "/velodyne/000000.bin")) GTEST_SKIP() << "no " << dir;
  PointCloud cloud = io::read_kitti_bin(dir + "/velodyne/000000.bin");
  const std::vector<Label> labels = io::read_labels(dir + "/labels/000000.label", cloud.size());
  correct_vertical_angle(cloud.xyz, 0.25);
  const SensorConfig sensor = sensor_preset("HDL-64E");
  const SegmentationResult seg = segment(cloud.xyz, sensor, SegmentationConfig{});
  const FeatureConfig config;
  const FeatureSet fs = extract_features(cloud.xyz, seg, config);
  EXPECT_GT(fs.f_e.size(), 200u);
  EXPECT_LE(static_cast<int>(fs.f_e.size()), config.N_fe * config.N_div * sensor.N_scan);
  EXPECT_GT(fs.F_e.size(), 2 * fs.f_e.size());
  EXPECT_GT(fs.f_p.size(), 500u);
  EXPECT_GT(fs.F_p.size(), 5000u);
  EXPECT_LT(fs.F_p.size(), cloud.size() / 3);
  for (int i : fs.F_e_index) EXPECT_GT(seg.point_label[static_cast<std::size_t>(i)], 0);
  int moving = 0;
  for (int i : fs.f_p_index) {
    EXPECT_EQ(seg.point_label[static_cast<std::size_t>(i)], kGroundLabel);
    moving += semantic::is_moving(labels[static_cast<std::size_t>(i)]);
  }
  EXPECT_LT(moving, 5) << "f_p lies on the road, not on moving objects";
}
