// Degeneracy detection and solution remapping with known answers: in a corridor the axis is the
// unconstrained direction and the estimate keeps the prior's value along it while the other
// directions are solved, closed at both ends nothing is flagged; a simulated drive through a
// tunnel is flagged along the tunnel axis, the street before and after it is not, and the
// position error along the axis stays bounded; the scan-to-map registration estimates a translation
// its share test alone leaves unconstrained where the odometry constrains it (a highway's travel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "dloam/core/degeneracy.hpp"
#include "dloam/core/registration.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "pose_test_util.hpp"
#include "sim_test_util.hpp"

using namespace dloam;

namespace {

using test::make_pose;

std::vector<Vec3> transformed(const Pose& T, const std::vector<Vec3>& pts) {
  std::vector<Vec3> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(T * p);
  return out;
}

/// Ground, ceiling and two smooth walls along x (a tunnel 60 m long); `end_walls`: closed at both
/// ends, which constrains the travel along x.
std::vector<Vec3> corridor(bool end_walls) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> planes;
  for (int i = 0; i < 3000; ++i) planes.emplace_back(30 * u(rng), 5.5 * u(rng), -1.8);
  for (int i = 0; i < 2000; ++i) planes.emplace_back(30 * u(rng), 5.5 * u(rng), 4.2);
  for (int i = 0; i < 2000; ++i) planes.emplace_back(30 * u(rng), 5.5, 3 * u(rng) + 1.2);
  for (int i = 0; i < 2000; ++i) planes.emplace_back(30 * u(rng), -5.5, 3 * u(rng) + 1.2);
  if (end_walls)
    for (double x : {-30.0, 30.0})
      for (int i = 0; i < 2000; ++i) planes.emplace_back(x, 5.5 * u(rng), 3 * u(rng) + 1.2);
  return planes;
}

}  // namespace

TEST(Degeneracy, CorridorAxisKeepsThePriorAndTheOtherDirectionsAreSolved) {
  const std::vector<Vec3> planes = corridor(false);
  FeatureMap target;
  target.planes.build(planes);
  const Pose truth = make_pose(0.02, {0.8, 0.1, 0.05});
  const FeatureSource src{{}, transformed(truth.inverse(), planes), {}, {}};
  RegistrationParams p;
  p.max_iterations = 30;
  // The mechanism alone: a direction is unconstrained below 50 features' worth (roll, about
  // 150 here, stays constrained; the default share of the matches would flag it in this small tube).
  p.degeneracy.min_features = 50.0;
  p.degeneracy.min_fraction = 0.0;
  p.prior = make_pose(0.0, {0.6, 0.0, 0.0});  // constant velocity: 0.2 m short along the axis
  const RegistrationResult r = register_features(src, target, Pose::Identity(), p);
  ASSERT_TRUE(r.degenerate());
  EXPECT_EQ(r.degeneracy.unconstrained, 1);
  EXPECT_EQ(unconstrained_names(r.degeneracy), "x");
  // Along the axis the estimate is the prior, not the initial guess and not a drift.
  EXPECT_NEAR(r.T.translation().x(), 0.6, 0.01);
  // The constrained directions are solved.
  EXPECT_NEAR(r.T.translation().y(), 0.1, 0.01);
  EXPECT_NEAR(r.T.translation().z(), 0.05, 0.01);
  EXPECT_NEAR(Eigen::AngleAxisd(r.T.rotation()).angle(), 0.02, 0.002);

  // Closed at both ends, the same motion is constrained in every direction and solved.
  const std::vector<Vec3> closed = corridor(true);
  FeatureMap closed_target;
  closed_target.planes.build(closed);
  const FeatureSource closed_src{{}, transformed(truth.inverse(), closed), {}, {}};
  const RegistrationResult c = register_features(closed_src, closed_target, Pose::Identity(), p);
  EXPECT_FALSE(c.degenerate()) << unconstrained_names(c.degeneracy);
  EXPECT_NEAR(c.T.translation().x(), 0.8, 0.01);
  EXPECT_NEAR(c.T.translation().y(), 0.1, 0.01);
}

namespace {
/// The default pipeline for `sensor` with the geometric detector.
PipelineConfig geometric_config(const SensorConfig& sensor) {
  PipelineConfig config;
  config.sensor = sensor;
  config.detection.detector = Detector::kGeometric;
  return config;
}

/// How many of `d`'s unconstrained directions lie mostly along `axis`.
int unconstrained_along(const Degeneracy& d, const char* axis) {
  int n = 0;
  for (int a = 0; a < d.unconstrained; ++a) n += direction_name(d.eigenvectors.col(a)) == axis;
  return n;
}

/// A normal matrix in twist coordinates [rad; m] with the given translation eigenvalues (features'
/// worth) along the axes and well-constrained rotations.
Mat6 normal_matrix(const Vec3& translation, const DegeneracyConfig& config) {
  Vec6 scaled;
  scaled << 5000.0, 5000.0, 5000.0, translation;
  Mat6 H = Mat6(scaled.asDiagonal());
  H.topRows<3>() *= config.rotation_radius;  // scaled -> twist coordinates (D^-1 S D^-1)
  H.leftCols<3>() *= config.rotation_radius;
  return H;
}
}  // namespace

TEST(Degeneracy, ATranslationOnlyTheMapsShareLeavesUnconstrainedIsEstimatedWhereTheOdometryConstrainsIt) {
  const DegeneracyConfig config;  // min_features 30, min_fraction 0.08, odometry_min_features 60
  // The map: 6000 matches (share threshold 480), 150 features' worth along x (a highway's posts).
  const Mat6 map = normal_matrix({150.0, 3000.0, 4000.0}, config);
  EXPECT_EQ(unconstrained_names(analyse_degeneracy(map, 6000, kAllDof, config)), "x");

  // The odometry of the same scan, in the previous scan's frame, turned 90 deg from the map's:
  // its y is the map's x. 600 matches, 80 features' worth along it.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const Degeneracy odometry =
      analyse_degeneracy(normal_matrix({500.0, 80.0, 500.0}, config), 600, kAllDof, config);
  EXPECT_FALSE(odometry.degenerate());
  const SecondOpinion seen = second_opinion(odometry, R);
  EXPECT_NEAR(seen.scaled_normal_matrix(3, 3), 80.0, 1e-6);  // the map's x
  EXPECT_NEAR(seen.scaled_normal_matrix(4, 4), 500.0, 1e-6);
  EXPECT_EQ(seen.matches, 600);
  EXPECT_FALSE(analyse_degeneracy(map, 6000, kAllDof, config, {}, &seen).degenerate());

  // An odometry with 40 features' worth along the map's x (below odometry_min_features; a tunnel's
  // ring patterns): the map's x stays unconstrained.
  const Degeneracy weak =
      analyse_degeneracy(normal_matrix({500.0, 40.0, 500.0}, config), 600, kAllDof, config);
  const SecondOpinion weak_seen = second_opinion(weak, R);
  EXPECT_EQ(unconstrained_names(analyse_degeneracy(map, 6000, kAllDof, config, {}, &weak_seen)), "x");

  // Below min_features the map's direction stays unconstrained whatever the odometry says.
  const Mat6 bare = normal_matrix({20.0, 3000.0, 4000.0}, config);
  EXPECT_EQ(unconstrained_names(analyse_degeneracy(bare, 6000, kAllDof, config, {}, &seen)), "x");

  // odometry_min_features 0: the map's own tests decide.
  DegeneracyConfig off = config;
  off.odometry_min_features = 0.0;
  EXPECT_EQ(unconstrained_names(analyse_degeneracy(map, 6000, kAllDof, off, {}, &seen)), "x");
}

TEST(Degeneracy, SimulatedTunnelIsFlaggedAlongItsAxisAndTheErrorAlongItStaysBounded) {
  // 200 m: 30 m of street, 140 m of tunnel with smooth walls, 30 m of street; 10 m/s, no traffic.
  constexpr int kFrames = 200;
  const SensorConfig sensor = sensor_preset("VLP-16");
  sim::Simulator sim = test::make_simulator(sim::ScenarioKind::Tunnel, kFrames, 4, sensor, 0.0);
  Pipeline pipeline(geometric_config(sensor));
  std::vector<ScanResult> results;
  std::vector<Pose> gt;
  for (int k = 0; k < kFrames; ++k) {
    const sim::SimFrame f = sim.frame(k);
    results.push_back(pipeline.process(f.scan.cloud));
    gt.push_back(f.pose);
  }
  const std::vector<Pose> est = pipeline.trajectory();
  ASSERT_EQ(est.size(), gt.size());

  // Deep in the tunnel the map leaves the axis (the sensor's x) unconstrained.
  int tunnel = 0, axis = 0;
  for (int k = 60; k < 140; ++k) {
    ++tunnel;
    axis += unconstrained_along(results[static_cast<std::size_t>(k)].map_degeneracy, "x");
  }
  std::printf("tunnel scans 60-139: %d of %d flagged along x\n", axis, tunnel);
  EXPECT_GE(axis, tunnel * 9 / 10);
  // The same street, before the tunnel and after it: x is constrained.
  int street_axis = 0;
  for (int k : {10, 15, 20, 185, 190, 195}) {
    const Degeneracy& d = results[static_cast<std::size_t>(k)].map_degeneracy;
    EXPECT_GT(d.free, 0);
    street_axis += unconstrained_along(d, "x");
  }
  EXPECT_EQ(street_axis, 0);

  // Position error along the drive (in the first pose's frame): bounded along the axis at every
  // scan (without the remapping the estimate stalls in the tunnel, about 1 m per scan).
  double worst_axis = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < gt.size(); ++k) {
    const Vec3 e =
        (est.front().inverse() * est[k]).translation() - (gt.front().inverse() * gt[k]).translation();
    worst_axis = std::max(worst_axis, std::abs(e.x()));
    worst = std::max(worst, e.norm());
  }
  std::printf("worst position error: along the axis %.3f m, overall %.3f m over %d scans\n", worst_axis,
              worst, kFrames);
  EXPECT_LT(worst_axis, 1.5);
  EXPECT_LT(worst, 3.0);
}

TEST(Degeneracy, OnAHighwayTheMapCorrectsTheDriftAlongTheRoadThatTheOdometryMeasures) {
  // 150 m of highway at 25 m/s with traffic: guard rails, posts and a few signs along the road
  // give the map some hundred features' worth of its thousands along the travel, under its share
  // threshold; the odometry's own features often measure the travel. Two pipelines over the same
  // scans: the default (the map asks the odometry) and the map's own tests alone.
  constexpr int kFrames = 60;
  const SensorConfig sensor = sensor_preset("HDL-64E");
  sim::Simulator sim = test::make_simulator(sim::ScenarioKind::Highway, kFrames, 12, sensor, 3.0);
  const PipelineConfig config = geometric_config(sensor);
  PipelineConfig alone = config;
  alone.degeneracy.odometry_min_features = 0.0;
  Pipeline asking(config), own(alone);
  std::vector<Pose> gt;
  int flagged_asking = 0, flagged_own = 0, mapped = 0;
  for (int k = 0; k < kFrames; ++k) {
    const sim::SimFrame f = sim.frame(k);
    const ScanResult a = asking.process(f.scan.cloud);
    const ScanResult o = own.process(f.scan.cloud);
    gt.push_back(f.pose);
    if (k < 10) continue;
    ++mapped;
    flagged_asking += unconstrained_along(a.map_degeneracy, "x") > 0;
    flagged_own += unconstrained_along(o.map_degeneracy, "x") > 0;
  }
  const test::EndPointError ea = test::end_point_error(asking.trajectory(), gt);
  const test::EndPointError eo = test::end_point_error(own.trajectory(), gt);
  const double path = ea.truth.translation().norm();
  std::printf("scans 10-%d with x unconstrained in the map: asking the odometry %d, alone %d of %d\n",
              kFrames - 1, flagged_asking, flagged_own, mapped);
  std::printf("end-point error over %.1f m: asking %.3f m, alone %.3f m\n", path,
              ea.error.translation().norm(), eo.error.translation().norm());
  // The map alone leaves the travel to the odometry on nearly every scan; asked, it estimates it
  // on the scans where the odometry measured it (15 of 50 on this drive).
  EXPECT_GE(flagged_own, mapped * 8 / 10);
  EXPECT_LE(flagged_asking, flagged_own - mapped / 5);
  // Tracked along the road either way (0.32 m and 0.30 m measured, 0.2 %).
  EXPECT_LT(ea.error.translation().norm(), 0.005 * path);
  EXPECT_LT(eo.error.translation().norm(), 0.005 * path);
}

TEST(Degeneracy, TheMapKeepsAPredictionOnlyWhereItCanTrustIt) {
  // A corridor with one end wall of a few hundred points: the travel along it is measured, but by
  // a small share of the matches, under degeneracy.min_fraction. The map's prediction is 0.3 m off
  // along the axis. Kept when nothing says how far it can be off (the odometry's step), estimated
  // when its step was reported lost (any error possible).
  std::vector<Vec3> planes = corridor(false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 400; ++i) planes.emplace_back(30.0, 5.5 * u(rng), 3 * u(rng) + 1.2);
  MappingConfig config;
  config.loop_closure = false;
  const Pose truth = make_pose(0.0, {0.5, 0.0, 0.0});
  const FeatureSource first{{}, planes, {}, {}};
  const FeatureSource second{{}, transformed(truth.inverse(), planes), {}, {}};
  const Pose predicted = make_pose(0.0, {0.8, 0.0, 0.0});
  const auto run = [&](const PriorError& error) {
    Mapper mapper(config, 10.0, DegeneracyConfig{});
    mapper.process(0, first, Pose::Identity(), true);
    return mapper.process(1, second, predicted, false, std::nullopt, error);
  };
  const MappingResult kept = run({});
  ASSERT_TRUE(kept.registration.degenerate());
  EXPECT_EQ(unconstrained_names(kept.registration.degeneracy), "x");
  EXPECT_NEAR(kept.pose.translation().x(), 0.8, 0.01);
  const MappingResult estimated = run({M_PI, 100.0});
  EXPECT_EQ(unconstrained_names(estimated.registration.degeneracy), "x");  // reported all the same
  EXPECT_NEAR(estimated.pose.translation().x(), 0.5, 0.02);
  EXPECT_NEAR(estimated.pose.translation().y(), 0.0, 0.01);
}
