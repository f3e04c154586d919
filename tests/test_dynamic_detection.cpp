// Dynamic-object detection (paper III.D.3, eq. 13) on an analytic scene: a 32-beam sensor driving
// forward past a building and a pole while a car comes towards it. Checks the speed matrix of the
// moved object, the cluster labelling with ground re-verification, the per-point labels and the
// pseudo-static tracking of a car that stops (type 2), the speed matrix's fast projection and the
// first scan pair's forward search (static surface score).
#include <gtest/gtest.h>

#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/object_tracker.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "seg_test_scene.hpp"

using namespace dloam;
using test::detail::ray_box;
using test::detail::ray_cylinder;

namespace {

enum Id { kGround = 0, kBuilding, kPole, kCar };

struct Frame {
  std::vector<Vec3> points;  ///< sensor frame
  std::vector<int> id;
  SegmentationResult seg;
};

/// One ray per pixel centre from a sensor at (sx, 0, 0) (world frame, 1.73 m above the ground);
/// the car is a 4 x 2 x 1.5 m box whose rear starts at x = car_x.
Frame cast(double sx, double car_x, const SensorConfig& sensor) {
  const test::Box building{{22.0 - sx, -15.0, -1.73}, {30.0 - sx, 15.0, 4.0}};
  const test::Cylinder pole{9.0 - sx, -5.0, 0.15, -1.73, 2.5};
  const test::Box car{{car_x - sx, -1.0, -1.73}, {car_x + 4.0 - sx, 1.0, -0.23}};
  Frame f;
  test::for_each_pixel_ray(sensor, [&](int, int, const Vec3& d) {
    test::Nearest n{test::ground_distance(d, 1.73), kGround};
    n.consider(ray_box(d, building), kBuilding);
    n.consider(ray_cylinder(d, pole), kPole);
    n.consider(ray_box(d, car), kCar);
    if (n.t > sensor.max_range) return;
    f.points.push_back(n.t * d);
    f.id.push_back(n.id);
  });
  f.seg = segment(f.points, sensor, SegmentationConfig{});
  return f;
}

Pose translation(double x) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(x, 0, 0);
  return T;
}

RangeImage image_of(const Frame& f, const SensorConfig& s) { return project(f.points, s); }

/// Fraction of the pixels hitting `which` whose speed passes `pred`.
template <class Pred>
double fraction(const Frame& f, const SpeedMatrix& S, int which, Pred pred) {
  int n = 0, ok = 0;
  for (std::size_t px = 0; px < S.speed.size(); ++px) {
    const int i = f.seg.image.point_of_pixel[px];
    if (i < 0 || f.id[static_cast<std::size_t>(i)] != which || S.speed[px] < 0.0f) continue;
    ++n;
    ok += pred(S.speed[px]);
  }
  return n > 0 ? static_cast<double>(ok) / n : -1.0;
}

/// The cluster holding most points of object `which`.
int cluster_of(const Frame& f, int which) {
  std::vector<int> count(static_cast<std::size_t>(f.seg.num_clusters) + 1, 0);
  for (std::size_t i = 0; i < f.points.size(); ++i)
    if (f.id[i] == which && f.seg.point_label[i] > 0) ++count[static_cast<std::size_t>(f.seg.point_label[i])];
  return static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
}

}  // namespace

TEST(SpeedMatrix, MovedObjectIsFastStaticSceneIsNot) {
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 12.0, s);  // the car 12 m ahead
  const Frame cur = cast(0.5, 11.0, s);   // ego +0.5 m, the car -1 m (oncoming)
  const SpeedMatrix S =
      compute_speed_matrix(cur.seg.image, cur.points, translation(0.5), image_of(prev, s).range, s);
  const double car_fast = fraction(cur, S, kCar, [](float v) { return v > 0.5f; });
  const double building_slow = fraction(cur, S, kBuilding, [](float v) { return v < 0.05f; });
  const double ground_slow = fraction(cur, S, kGround, [](float v) { return v < 0.05f; });
  std::printf("car pixels > 0.5 m: %.3f, building < 5 cm: %.3f, ground < 5 cm: %.3f\n", car_fast,
              building_slow, ground_slow);
  EXPECT_GT(car_fast, 0.85);  // all but the silhouette edges
  EXPECT_GT(building_slow, 0.9);
  EXPECT_GT(ground_slow, 0.9);
  // With the ego-motion ignored the static scene would look like it moved.
  const SpeedMatrix wrong =
      compute_speed_matrix(cur.seg.image, cur.points, Pose::Identity(), image_of(prev, s).range, s);
  EXPECT_LT(fraction(cur, wrong, kBuilding, [](float v) { return v < 0.05f; }), 0.2);
}

TEST(DynamicDetector, LabelsTheMovingCarClusterOnly) {
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 12.0, s);
  const Frame cur = cast(0.5, 11.0, s);
  const SpeedMatrix S =
      compute_speed_matrix(cur.seg.image, cur.points, translation(0.5), image_of(prev, s).range, s);
  DetectionConfig cfg = thresholds_over(DetectionConfig{}, 0.1);  // scans 0.1 s apart
  cfg.v_static = 0.2;
  cfg.v_ground = 0.1;
  const DetectionResult det = detect_dynamic(cur.seg, S, cfg);
  const int car = cluster_of(cur, kCar), building = cluster_of(cur, kBuilding), pole = cluster_of(cur, kPole);
  ASSERT_GT(car, 0);
  ASSERT_NE(car, building);
  EXPECT_TRUE(det.cluster_dynamic[static_cast<std::size_t>(car)]);
  EXPECT_FALSE(det.cluster_dynamic[static_cast<std::size_t>(building)]);
  EXPECT_FALSE(det.cluster_dynamic[static_cast<std::size_t>(pole)]);
  EXPECT_EQ(det.num_dynamic, 1);
  // Per-point labels: the car's points moving, everything else static.
  const auto labels = point_labels(cur.seg, det);
  std::size_t car_moving = 0, car_points = 0, other_moving = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const bool moving = semantic::is_moving(labels[i]);
    if (cur.id[i] == kCar)
      car_points++, car_moving += moving;
    else
      other_moving += moving;
  }
  EXPECT_GT(car_moving, 0.85 * car_points);
  EXPECT_EQ(other_moving, 0u);
  // Ground re-verification: ground pixels the car uncovered (it was there before) are rejected, few others.
  std::size_t rejected = 0, ground = 0;
  for (std::size_t px = 0; px < det.ground_rejected.size(); ++px) {
    ground += cur.seg.pixel_label[px] == kGroundLabel;
    rejected += det.ground_rejected[px];
  }
  EXPECT_GT(rejected, 0u);
  EXPECT_LT(rejected, ground / 50);
}

TEST(DynamicDetector, StaticSceneHasNoDynamicCluster) {
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 12.0, s);
  const Frame cur = cast(0.5, 12.0, s);  // the car parked
  const SpeedMatrix S =
      compute_speed_matrix(cur.seg.image, cur.points, translation(0.5), image_of(prev, s).range, s);
  DetectionConfig cfg = thresholds_over(DetectionConfig{}, 0.1);  // scans 0.1 s apart
  cfg.v_static = 0.2;
  EXPECT_EQ(detect_dynamic(cur.seg, S, cfg).num_dynamic, 0);
  EXPECT_THROW(detect_dynamic(cur.seg, SpeedMatrix{}, cfg), InputError);
}

TEST(ObjectTracker, StopAndGoCarIsTypeTwoThenTypeOne) {
  const SensorConfig s = test::scene_sensor();
  DetectionConfig cfg = thresholds_over(DetectionConfig{}, 0.1);  // scans 0.1 s apart
  cfg.v_static = 0.2;
  // Car positions over five scans, ego +0.5 m per scan: moving, stopped, stopped, moving again.
  const double car_x[] = {14.0, 13.0, 13.0, 13.0, 12.0};
  ObjectTracker tracker;
  std::vector<TrackResult> tracks;
  std::vector<int> car_dynamic;
  Frame prev = cast(0.0, car_x[0], s);
  for (int k = 1; k < 5; ++k) {
    const Frame cur = cast(0.5 * k, car_x[k], s);
    const SpeedMatrix S =
        compute_speed_matrix(cur.seg.image, cur.points, translation(0.5), image_of(prev, s).range, s);
    DetectionResult det = detect_dynamic(cur.seg, S, cfg);
    tracks.push_back(tracker.update(cur.seg, S, det, 0.75));
    car_dynamic.push_back(det.cluster_dynamic[static_cast<std::size_t>(cluster_of(cur, kCar))]);
    const int car = cluster_of(cur, kCar);
    if (k >= 2) {
      EXPECT_GT(tracks.back().previous_cluster[static_cast<std::size_t>(car)], 0) << "scan " << k;
    }
    if (k == 2) {
      EXPECT_EQ(tracks.back().transition[static_cast<std::size_t>(car)], Transition::kDynamicToStatic);
    }
    if (k == 3) {
      EXPECT_EQ(tracks.back().transition[static_cast<std::size_t>(car)], Transition::kNone);
    }
    if (k == 4) {
      EXPECT_EQ(tracks.back().transition[static_cast<std::size_t>(car)], Transition::kStaticToDynamic);
    }
    prev = cur;
  }
  EXPECT_EQ(car_dynamic, (std::vector<int>{1, 0, 0, 1}));
  // First update has no previous scan; the stop gives exactly one type-2 object with marked pixels.
  EXPECT_EQ(tracks[0].type1 + tracks[0].type2, 0);
  EXPECT_EQ(tracks[1].type2, 1);
  EXPECT_GT(std::count(tracks[1].pseudo_static.begin(), tracks[1].pseudo_static.end(), 1), 50);
  EXPECT_EQ(tracks[2].type1 + tracks[2].type2, 0);
  EXPECT_EQ(tracks[3].type1, 1);
}

TEST(SpeedMatrix, LandingPixelMatchesTheExactProjection) {
  // The speed matrix projects with a sin(elevation) table and a polynomial atan2: the previous pixel
  // must be the one eqs. 4-5 give (up to points on a pixel border).
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 12.0, s);
  const Frame cur = cast(0.5, 11.0, s);
  Vec6 xi;
  xi << 0.01, -0.02, 0.05, 0.5, 0.1, 0.02;
  const Pose T = exp_se3(xi);
  const SpeedMatrix S = compute_speed_matrix(cur.seg.image, cur.points, T, image_of(prev, s).range, s);
  std::size_t n = 0, same = 0;
  for (std::size_t px = 0; px < S.previous_pixel.size(); ++px) {
    const int i = cur.seg.image.point_of_pixel[px];
    if (i < 0) continue;
    const Vec3 q = T * cur.points[static_cast<std::size_t>(i)];
    const int row = s.row_of_elevation(point_elevation_deg(q));
    const int exact = row < 0 ? -1 : row * s.Horizon_SCAN + azimuth_column(q.x(), q.y(), s.Horizon_SCAN);
    ++n;
    same += S.previous_pixel[px] == exact;
  }
  ASSERT_GT(n, 1000u);
  EXPECT_GT(static_cast<double>(same) / n, 0.995);
}

TEST(SpeedMatrix, StaticAreaPeaksAtTheEgoMotionNotAtACoMovingCar) {
  // First scan pair, no motion prior: the ego drives 2 m, the car ahead drives with it (it looks
  // static at dx = 0). The static surface (r^2-weighted) is largest at the true motion.
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 8.0, s);
  const Frame cur = cast(2.0, 10.0, s);
  const auto range = image_of(prev, s).range;
  const std::vector<int> pixels = static_area_pixels(cur.seg.image, cur.points, cur.seg.pixel_label, 1);
  auto score = [&](const Pose& T) {
    return static_area(cur.seg.image, cur.points, pixels, T, range, s, 0.2);
  };
  EXPECT_GT(score(translation(2.0)), 1.5 * score(translation(0.0)));
  const Pose found = search_forward_translation(Pose::Identity(), 4.0, 0.2, score);
  EXPECT_NEAR(found.translation().x(), 2.0, 0.21);
  EXPECT_NEAR(found.translation().y(), 0.0, 1e-12);
}

TEST(SpeedMatrix, StaticAreaIgnoresTerrainTheGroundSegmentationMissed) {
  // Far terrain the ground segmentation left as a cluster (a highway verge) is seen at grazing
  // incidence: with no motion its rows repeat exactly, with any motion they land on rows of very
  // different range. Counted, it outweighs the building and puts the search at standing still.
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(0.0, 8.0, s);
  Frame cur = cast(2.0, 10.0, s);
  const auto range = image_of(prev, s).range;
  std::size_t relabelled = 0;
  for (std::size_t px = 0; px < cur.seg.pixel_label.size(); ++px) {
    const int i = cur.seg.image.point_of_pixel[px];
    if (i < 0 || cur.id[static_cast<std::size_t>(i)] != kGround ||
        cur.points[static_cast<std::size_t>(i)].norm() < 15.0)
      continue;
    cur.seg.pixel_label[px] = cur.seg.num_clusters + 1;
    ++relabelled;
  }
  ASSERT_GT(relabelled, 3000u);
  const std::vector<int> pixels = static_area_pixels(cur.seg.image, cur.points, cur.seg.pixel_label, 1);
  auto score = [&](const Pose& T) {
    return static_area(cur.seg.image, cur.points, pixels, T, range, s, 0.2);
  };
  EXPECT_GT(score(translation(2.0)), 1.5 * score(translation(0.0)));
  const Pose found = search_forward_translation(Pose::Identity(), 4.0, 0.2, score);
  EXPECT_NEAR(found.translation().x(), 2.0, 0.21);
}
TEST(ObjectTracker, HoldsOnlyConfirmedDynamicObjects) {
  // One cluster over a 1 x 10 image that lands on itself. Its static fraction 0.6 is above alpha
  // (static) but below alpha_tracked: only an object dynamic in the last two scans is held dynamic.
  SegmentationResult seg;
  seg.num_clusters = 1;
  seg.pixel_label.assign(10, 1);
  SpeedMatrix S;
  S.previous_pixel = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  auto scan = [&](ObjectTracker& tracker, bool detected) {
    DetectionResult det;
    det.cluster_dynamic = {0, static_cast<std::uint8_t>(detected)};
    det.static_fraction = {-1.0, detected ? 0.2 : 0.6};
    tracker.update(seg, S, det, 0.75);
    return det.cluster_dynamic[1] != 0;
  };
  ObjectTracker once;
  EXPECT_TRUE(scan(once, true));
  EXPECT_FALSE(scan(once, false));  // a single detection is not carried on
  ObjectTracker twice;
  EXPECT_TRUE(scan(twice, true));
  EXPECT_TRUE(scan(twice, true));
  EXPECT_TRUE(scan(twice, false));  // held by the hysteresis
  EXPECT_TRUE(scan(twice, false));
}
