// Segmentation (paper III.C): ground (eq. 7), range-image clustering, labels per point, on an
// analytic scene with known answers and on a real KITTI scan.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "dloam/core/ground.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/io/kitti.hpp"
#include "seg_test_scene.hpp"

using namespace dloam;
using dloam::test::Scene;

namespace {

const Scene& scene() {
  static const Scene s = test::make_scene();
  return s;
}

// Labels of the points that hit `what` (and stand at least `min_height` above the ground).
std::set<int> labels_of(const Scene& s, const SegmentationResult& seg, int what, double min_height = -1.0) {
  std::set<int> out;
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (s.hit[i] == what && test::height_above_ground(s, s.points[i]) >= min_height)
      out.insert(seg.point_label[i]);
  return out;
}

}  // namespace

TEST(Ground, AutoSearchRowsAreTheBeamsBelowMinusOneDegree) {
  SegmentationConfig c;
  EXPECT_EQ(ground_search_rows(sensor_preset("VLP-16"), c), 8);  // -15..-1 deg: LeGO-LOAM's rows 0..7
  EXPECT_EQ(ground_search_rows(test::scene_sensor(), c), 28);    // -24.9 + 27 * 0.868 = -1.46 deg
  c.N_ground_rows = 5;
  EXPECT_EQ(ground_search_rows(sensor_preset("VLP-16"), c), 5);
  c.N_ground_rows = 100;
  EXPECT_EQ(ground_search_rows(sensor_preset("VLP-16"), c), 16);
}

TEST(Segmentation, GroundIsExactlyTheGroundPlane) {
  const Scene& s = scene();
  const SegmentationResult seg = segment(s.points, s.sensor, SegmentationConfig{});
  int ground_points = 0, wall_base = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    ASSERT_GE(seg.image.pixel_of_point(i), 0) << "every scene point lies in the image";
    if (s.hit[i] == test::kGround) {
      ++ground_points;
      EXPECT_EQ(seg.point_label[i], kGroundLabel) << "ground point " << i << " row " << s.row[i];
    } else if (seg.point_label[i] == kGroundLabel) {
      // Only the foot of an object standing on the ground may pass eq. 7.
      EXPECT_LT(test::height_above_ground(s, s.points[i]), 0.3)
          << "object point " << i << " hit " << s.hit[i];
      ++wall_base;
    }
  }
  EXPECT_GT(ground_points, 10000);
  EXPECT_EQ(seg.num_ground_pixels, ground_points + wall_base);
  EXPECT_TRUE(seg.ground_plane_valid);
  EXPECT_NEAR(seg.ground_normal.z(), 1.0, 1e-6);
  EXPECT_NEAR(seg.ground_height, s.height, 2e-3);  // object feet within 0.15 m take part in the fit
}

TEST(Segmentation, GroundPlaneFollowsATiltedSensor) {
  const Scene& s = scene();
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.05, Vec3::UnitX()) * Eigen::AngleAxisd(-0.03, Vec3::UnitY())).toRotationMatrix();
  std::vector<Vec3> tilted;
  for (const Vec3& p : s.points) tilted.push_back(R * p);
  const SegmentationResult seg = segment(tilted, s.sensor, SegmentationConfig{});
  ASSERT_TRUE(seg.ground_plane_valid);
  EXPECT_GT(seg.ground_normal.dot(R * Vec3::UnitZ()), std::cos(0.2 * M_PI / 180.0));
  EXPECT_NEAR(seg.ground_height, s.height, 0.01);
  // Ground hits in the searched rows are ground (farther ground now appears above -1 deg, and
  // some hits left the field of view).
  const int search_rows = ground_search_rows(s.sensor, SegmentationConfig{});
  int ground_hits = 0, labelled = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (s.hit[i] != test::kGround || seg.image.pixel_of_point(i) < 0) continue;
    if (seg.image.row_of_point[i] >= search_rows) continue;
    ++ground_hits;
    labelled += seg.point_label[i] == kGroundLabel;
  }
  EXPECT_GT(ground_hits, 20000);
  EXPECT_GT(labelled, 0.99 * ground_hits);
}

TEST(Segmentation, PoleBuildingAndPostAreSeparateClusters) {
  const Scene& s = scene();
  const SegmentationResult seg = segment(s.points, s.sensor, SegmentationConfig{});
  const auto pole = labels_of(s, seg, test::kPole, 0.3);
  const auto building = labels_of(s, seg, test::kBuilding, 0.3);
  const auto post = labels_of(s, seg, test::kPost);
  ASSERT_EQ(pole.size(), 1u);
  ASSERT_EQ(building.size(), 1u);
  ASSERT_EQ(post.size(), 1u);
  EXPECT_GT(*pole.begin(), 0);
  EXPECT_GT(*building.begin(), 0);
  EXPECT_GT(*post.begin(), 0);
  EXPECT_NE(*pole.begin(), *building.begin());
  EXPECT_NE(*post.begin(), *pole.begin());
  // Five objects, one of them (the sign) rejected: pole, building, rear wall, post.
  EXPECT_EQ(seg.num_clusters, 4);
  const int max_label = *std::max_element(seg.pixel_label.begin(), seg.pixel_label.end());
  EXPECT_EQ(max_label, seg.num_clusters) << "kept clusters are numbered 1..m";
}

TEST(Segmentation, TinyClustersAreRejectedSmallTallOnesKept) {
  const Scene& s = scene();
  const SegmentationConfig config;
  const SegmentationResult seg = segment(s.points, s.sensor, config);
  std::set<int> sign_rows, post_rows;
  int sign_pixels = 0, post_pixels = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (s.hit[i] == test::kSign) ++sign_pixels, sign_rows.insert(s.row[i]);
    if (s.hit[i] == test::kPost) ++post_pixels, post_rows.insert(s.row[i]);
  }
  // Preconditions of the scene: the sign is too flat, the post small but tall enough.
  ASSERT_GE(sign_pixels, config.N_min_cluster_small);
  ASSERT_LT(sign_pixels, config.N_min_cluster);
  ASSERT_LT(static_cast<int>(sign_rows.size()), config.N_min_cluster_rows);
  ASSERT_GE(post_pixels, config.N_min_cluster_small);
  ASSERT_LT(post_pixels, config.N_min_cluster);
  ASSERT_GE(static_cast<int>(post_rows.size()), config.N_min_cluster_rows);
  EXPECT_EQ(labels_of(s, seg, test::kSign), std::set<int>{kOutlierLabel});
  EXPECT_GT(*labels_of(s, seg, test::kPost).begin(), 0);
}

TEST(Segmentation, ClusterAcrossColumnZeroStaysOne) {
  const Scene& s = scene();
  const SegmentationResult seg = segment(s.points, s.sensor, SegmentationConfig{});
  const auto wall = labels_of(s, seg, test::kRearWall, 0.3);
  ASSERT_EQ(wall.size(), 1u);
  EXPECT_GT(*wall.begin(), 0);
  bool near_first = false, near_last = false;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (s.hit[i] != test::kRearWall) continue;
    near_first |= s.col[i] < 5;
    near_last |= s.col[i] >= s.sensor.Horizon_SCAN - 5;
  }
  EXPECT_TRUE(near_first && near_last) << "the wall must straddle column 0";
}

TEST(Segmentation, AngleThresholdSeparatesDepthJumps) {
  // Two surfaces side by side, 4 m apart in depth: one cluster each at 10 deg, and a tiny
  // threshold merges them (beta > 0 for any pair).
  SensorConfig sensor = test::scene_sensor();
  std::vector<Vec3> pts;
  for (int v = 20; v < 30; ++v)
    for (int u = 500; u < 540; ++u) {
      const double e = sensor.beam_elevation_deg(v) * M_PI / 180.0;
      const double a = M_PI - 2.0 * M_PI * (u + 0.5) / sensor.Horizon_SCAN;
      const double r = u < 520 ? 10.0 : 14.0;
      pts.emplace_back(r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a), r * std::sin(e));
    }
  SegmentationConfig config;
  config.N_ground_rows = 1;  // no ground rows here
  EXPECT_EQ(segment(pts, sensor, config).num_clusters, 2);
  config.segment_theta_deg = 0.01;
  EXPECT_EQ(segment(pts, sensor, config).num_clusters, 1);
}

TEST(Segmentation, PointLabelsForHiddenAndOutsidePoints) {
  const Scene& s = scene();
  std::vector<Vec3> pts = s.points;
  std::size_t pole_point = 0;
  while (s.hit[pole_point] != test::kPole || test::height_above_ground(s, s.points[pole_point]) < 1.0)
    ++pole_point;
  pts.push_back(1.01 * s.points[pole_point]);  // same pixel, farther: loses it
  pts.emplace_back(0.0, 0.0, 50.0);            // straight up, outside the field of view
  pts.emplace_back(0.3, 0.0, -0.1);            // closer than min_range
  const SegmentationResult seg = segment(pts, s.sensor, SegmentationConfig{});
  ASSERT_EQ(seg.point_label.size(), pts.size());
  const std::size_t hidden = s.points.size();
  EXPECT_EQ(seg.image.pixel_of_point(hidden), seg.image.pixel_of_point(pole_point));
  EXPECT_EQ(seg.image.point_of_pixel[static_cast<std::size_t>(seg.image.pixel_of_point(hidden))],
            static_cast<int>(pole_point));
  EXPECT_GT(seg.point_label[hidden], 0);
  EXPECT_EQ(seg.point_label[hidden], seg.point_label[pole_point]);
  EXPECT_EQ(seg.point_label[hidden + 1], kOutlierLabel);
  EXPECT_EQ(seg.point_label[hidden + 2], kOutlierLabel);
}

TEST(Segmentation, DeterministicAndIndependentOfPointOrder) {
  const Scene& s = scene();
  const SegmentationResult a = segment(s.points, s.sensor, SegmentationConfig{});
  const SegmentationResult b = segment(s.points, s.sensor, SegmentationConfig{});
  EXPECT_EQ(a.pixel_label, b.pixel_label);
  EXPECT_EQ(a.point_label, b.point_label);
  std::vector<std::size_t> perm(s.points.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  std::vector<Vec3> shuffled;
  for (std::size_t k : perm) shuffled.push_back(s.points[k]);
  const SegmentationResult c = segment(shuffled, s.sensor, SegmentationConfig{});
  EXPECT_EQ(a.pixel_label, c.pixel_label);
  for (std::size_t k = 0; k < perm.size(); ++k) ASSERT_EQ(c.point_label[k], a.point_label[perm[k]]);
}

TEST(Segmentation, BadInputThrowsInputError) {
  const Scene& s = scene();
  SensorConfig bad = s.sensor;
  bad.N_scan = 1;
  EXPECT_THROW(segment(s.points, bad, SegmentationConfig{}), InputError);
  RangeImage wrong = project(s.points, s.sensor);
  wrong.row_of_point.pop_back();
  EXPECT_THROW(segment_image(s.points, wrong, s.sensor, SegmentationConfig{}), InputError);
  const SegmentationResult empty = segment({}, s.sensor, SegmentationConfig{});
  EXPECT_EQ(empty.num_clusters, 0);
  EXPECT_FALSE(empty.ground_plane_valid);
}

// Real HDL-64E scan: ground on the road and not on cars, objects in kept clusters.
TEST(SegmentationKitti, RealScanHasSoundGroundAndClusters) {
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir + "/velodyne/000000.bin")) GTEST_SKIP() << "no " << dir;
  PointCloud cloud = io::read_kitti_bin(dir + "/velodyne/000000.bin");
  const std::vector<Label> labels = io::read_labels(dir + "/labels/000000.label", cloud.size());
  correct_vertical_angle(cloud.xyz, 0.25);
  const SegmentationResult seg = segment(cloud.xyz, sensor_preset("HDL-64E"), SegmentationConfig{});
  ASSERT_TRUE(seg.ground_plane_valid);
  EXPECT_GT(seg.ground_normal.z(), 0.999);
  EXPECT_NEAR(seg.ground_height, 1.73, 0.1);  // KITTI's Velodyne is mounted 1.73 m above the road
  EXPECT_GT(seg.num_clusters, 100);
  EXPECT_LT(seg.num_clusters, 1000);
  std::size_t objects = 0, objects_ground = 0, objects_clustered = 0, in_image = 0, ground = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (seg.image.pixel_of_point(i) < 0) continue;
    ++in_image;
    ground += seg.point_label[i] == kGroundLabel;
    if (semantic::class_of(labels[i]) < semantic::kCar) continue;  // cars, vehicles, people, moving or not
    ++objects;
    objects_ground += seg.point_label[i] == kGroundLabel;
    objects_clustered += seg.point_label[i] > 0;
  }
  EXPECT_GT(in_image, 0.95 * static_cast<double>(cloud.size()));
  EXPECT_GT(ground, 0.4 * static_cast<double>(in_image));
  EXPECT_LT(ground, 0.75 * static_cast<double>(in_image));
  ASSERT_GT(objects, 1000u);
  EXPECT_LT(objects_ground, 0.02 * static_cast<double>(objects));
  EXPECT_GT(objects_clustered, 0.9 * static_cast<double>(objects));
}
