// The refinement of T_coarse by range-image alignment (core/range_alignment.hpp): it recovers a
// known motion from a start as far off as a 16-beam pre-registration leaves it, also with
// traffic in view; normals of simple surfaces; and in the pipeline a VLP-16 street's buildings
// are no longer flagged as moving.
#include <gtest/gtest.h>

#include <cmath>

#include "dloam/core/deskew.hpp"
#include "dloam/core/range_alignment.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "sim_test_util.hpp"

using namespace dloam;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// Scan k of a simulated drive, de-skewed with its true sweep motion, and its range image.
struct TrueScan {
  std::vector<Vec3> points;
  RangeImage image;
  Pose pose;
};
TrueScan true_scan(sim::Simulator& simulator, int k) {
  const sim::SimFrame f = simulator.frame(k);
  const Pose sweep = simulator.sensor_pose(k, 0.0).inverse() * simulator.sensor_pose(k, 1.0);
  TrueScan s;
  s.points = deskew(f.scan.cloud.xyz, point_times(f.scan.cloud, true), sweep);
  s.image = project(s.points, simulator.options().sensor);
  s.pose = f.pose;
  return s;
}

/// The vertex map of `points` on the pixels of their range image `image`.
VertexMap vertex_map(const std::vector<Vec3>& points, const RangeImage& image) {
  std::vector<int> pixel(points.size());
  for (std::size_t i = 0; i < pixel.size(); ++i) pixel[i] = image.pixel_of_point(i);
  return make_vertex_map(points, pixel, image.rows, image.cols);
}

}  // namespace

TEST(RangeAlignment, NormalsOfAWallAndOfTheGroundFaceTheSensor) {
  // A wall at x = 10 m and the ground 1.7 m below, seen by a 16-beam image.
  const SensorConfig sensor = sensor_preset("VLP-16");
  std::vector<Vec3> points;
  for (int v = 0; v < sensor.N_scan; ++v) {
    const double el =
        (sensor.Pit_bottom + v * (sensor.fov_top - sensor.Pit_bottom) / (sensor.N_scan - 1)) * kDeg;
    for (int u = 0; u < 200; ++u) {
      const double az = (-10.0 + 0.1 * u) * kDeg;
      const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const double t_wall = 10.0 / d.x(), t_ground = d.z() < 0.0 ? -1.7 / d.z() : 1e9;
      points.push_back(std::min(t_wall, t_ground) * d);
    }
  }
  const RangeImage image = project(points, sensor);
  const VertexMap map = vertex_map(points, image);
  int wall = 0, ground = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int px = image.pixel_of_point(i);
    if (px < 0 || image.point_of_pixel[static_cast<std::size_t>(px)] != static_cast<int>(i)) continue;
    const Eigen::Vector3f n = surface_normal(map, px / image.cols, px % image.cols);
    if (n.isZero()) continue;
    if (std::abs(points[i].x() - 10.0) < 1e-6 && points[i].z() > -1.2) {  // wall, off its foot
      EXPECT_NEAR(n.x(), -1.0f, 1e-3f) << points[i].transpose();
      ++wall;
    } else if (std::abs(points[i].z() + 1.7) < 1e-6 && points[i].x() < 9.0) {
      EXPECT_NEAR(n.z(), 1.0f, 1e-3f) << points[i].transpose();
      ++ground;
    }
  }
  EXPECT_GT(wall, 500);
  EXPECT_GT(ground, 200);  // the rows below the wall's foot
}

TEST(RangeAlignment, RecoversTheTrueMotionFromAStartAsFarOffAsSixteenBeamObjectsLeaveIt) {
  // VLP-16 on a city street with three times the default traffic (a queue ahead of and behind the
  // ego, people, cyclists): scans 0 and 1, each de-skewed with its true motion.
  sim::Simulator simulator =
      test::make_simulator(sim::ScenarioKind::Urban, 20, 4, sensor_preset("VLP-16"), 3.0);
  const TrueScan a = true_scan(simulator, 0), b = true_scan(simulator, 1);
  const Pose truth = a.pose.inverse() * b.pose;  // current (b) -> previous (a)
  const VertexMap previous = vertex_map(a.points, a.image);
  // Errors measured for the PCA pre-registration on such drives: up to 1.9 deg and 0.16 m.
  Vec6 off;
  off << 1.0 * kDeg, -0.6 * kDeg, 0.8 * kDeg, 0.12, -0.1, 0.05;
  const Pose start = exp_se3(off) * truth;
  const AlignmentResult r =
      align_range_images(b.points, b.image.point_of_pixel, previous, simulator.options().sensor, start);
  ASSERT_TRUE(r.valid);
  const Pose err = truth.inverse() * r.T;
  std::printf("start error %.3f m %.3f deg -> %.4f m %.4f deg (%d pairs)\n",
              translation_norm(truth.inverse() * start), rotation_angle(truth.inverse() * start) / kDeg,
              translation_norm(err), rotation_angle(err) / kDeg, r.pairs);
  EXPECT_LT(translation_norm(err), 0.03);
  EXPECT_LT(rotation_angle(err), 0.1 * kDeg);
}

TEST(RangeAlignment, NoPreviousImageGivesNoResult) {
  const AlignmentResult r =
      align_range_images({Vec3(5, 0, 0)}, {0}, VertexMap{}, sensor_preset("VLP-16"), Pose::Identity());
  EXPECT_FALSE(r.valid);
}

TEST(RangeAlignment, SixteenBeamStreetBuildingsAreNotFlaggedMoving) {
  // The pipeline with the geometric detector on a VLP-16 city drive: with T_coarse from the PCA
  // objects alone, 1-6 % of the static points per scan (building facades along the street) came
  // out moving, and the odometry lost the features it needed.
  constexpr int kFrames = 15;
  sim::Simulator simulator = test::make_simulator(sim::ScenarioKind::Urban, 100, 1, sensor_preset("VLP-16"));
  std::size_t false_moving = 0, static_points = 0;
  for (bool refine : {false, true}) {
    PipelineConfig cfg;
    cfg.sensor = simulator.options().sensor;
    cfg.detection.detector = Detector::kGeometric;
    cfg.preregistration.refine = refine;
    Pipeline pipeline(cfg);
    false_moving = static_points = 0;
    for (int k = 0; k < kFrames; ++k) {
      const sim::SimFrame f = simulator.frame(k);
      const ScanResult r = pipeline.process(f.scan.cloud);
      for (std::size_t i = 0; k > 0 && i < r.labels.size(); ++i) {
        if (semantic::is_moving(f.scan.labels[i])) continue;
        false_moving += semantic::is_moving(r.labels[i]);
        ++static_points;
      }
    }
    std::printf("refine %d: static points labelled moving %.3f %%\n", refine,
                100.0 * static_cast<double>(false_moving) / static_cast<double>(static_points));
  }
  EXPECT_LT(static_cast<double>(false_moving), 0.002 * static_cast<double>(static_points));
}

TEST(RangeAlignment, VertexMapKeepsTheNearestPointOfEachPixelAndItsRange) {
  // Pixels 0 and 2 of a 1 x 3 image: two points in pixel 0 (the nearer wins, whatever the order),
  // one in pixel 2, none in pixel 1, and one point outside the image (-1).
  const std::vector<Vec3> points{Vec3(5, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 4), Vec3(1, 1, 1)};
  const std::vector<int> pixel{0, 0, 2, -1};
  VertexMap map;
  for (int pass = 0; pass < 2; ++pass) {  // filling again reuses the memory and gives the same map
    fill_vertex_map(points, pixel, 1, 3, map);
    ASSERT_EQ(map.point.size(), 3u);
    EXPECT_TRUE(map.point[0].isApprox(Eigen::Vector3f(0, 3, 0)));
    EXPECT_FLOAT_EQ(map.range[0], 3.0f);
    EXPECT_TRUE(map.point[1].isZero());
    EXPECT_EQ(map.range[1], 0.0f);
    EXPECT_FLOAT_EQ(map.range[2], 4.0f);
  }
}
