// Odometry and the whole pipeline on simulated scans with exact ground truth: a known rigid
// motion between two scans of a simulated dynamic street is recovered, and a short drive is
// tracked end to end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "sim_test_util.hpp"

using namespace dloam;

namespace {

sim::Simulator make_simulator() {
  return test::make_simulator(sim::ScenarioKind::Urban, 30, 11, sensor_preset("HDL-32E"));
}

}  // namespace

TEST(OdometrySim, RecoversTheKnownMotionBetweenTwoSimulatedScans) {
  sim::Simulator simulator = make_simulator();
  const SensorConfig sensor = simulator.options().sensor;
  PipelineConfig cfg;
  cfg.sensor = sensor;
  ScanToScanOdometry odometry(cfg.odometry);
  // Consecutive scans 0 and 1 (0.1 s, about 0.7 m apart), each de-skewed with its true motion so that only
  // the registration is tested.
  Pose gt_motion;
  OdometryResult result;
  for (int k : {0, 1}) {
    const sim::SimFrame f = simulator.frame(k);
    const Pose sweep = simulator.sensor_pose(k, 0.0).inverse() * simulator.sensor_pose(k, 1.0);
    const auto points = deskew(f.scan.cloud.xyz, point_times(f.scan.cloud, true), sweep);
    const auto seg = segment(points, sensor, cfg.segmentation);
    const auto feat = extract_features(points, seg, cfg.features);
    result = odometry.process({feat.f_e, feat.f_p, {}, {}}, feat.F_e, feat.F_p, Pose::Identity());
    gt_motion = k == 0 ? f.pose : gt_motion.inverse() * f.pose;  // ends as pose0^-1 * pose1
  }
  ASSERT_TRUE(result.initialized);
  std::printf("plane step: %d matches, degenerate %d; edge step: %d matches, degenerate %d, iterations %d\n",
              result.plane_step.plane_matches, result.plane_step.degenerate(), result.edge_step.edge_matches,
              result.edge_step.degenerate(), result.edge_step.iterations);
  const Pose err = result.motion.inverse() * gt_motion;
  std::printf("true motion %.3f m, %.3f deg; error %.4f m, %.4f deg\n", gt_motion.translation().norm(),
              rotation_angle(gt_motion) * 180 / M_PI, err.translation().norm(),
              rotation_angle(err) * 180 / M_PI);
  EXPECT_GT(gt_motion.translation().norm(), 0.5);
  EXPECT_LT(err.translation().norm(), 0.05);
  EXPECT_LT(rotation_angle(err), 0.3 * M_PI / 180.0);
}

TEST(OdometrySim, PipelineTracksAShortDynamicDrive) {
  sim::Simulator simulator = make_simulator();
  PipelineConfig cfg;
  cfg.sensor = simulator.options().sensor;
  Pipeline pipeline(cfg);
  const auto [err, gt_rel] = test::track(pipeline, simulator, 20);
  std::printf("20 scans, %.2f m: end-point error %.4f m, %.4f deg\n", gt_rel.translation().norm(),
              err.translation().norm(), rotation_angle(err) * 180 / M_PI);
  EXPECT_GT(gt_rel.translation().norm(), 10.0);
  EXPECT_LT(err.translation().norm(), 0.02 * gt_rel.translation().norm());
  EXPECT_LT(rotation_angle(err), 0.5 * M_PI / 180.0);
}

TEST(OdometrySim, NoSteadyTiltBiasFromTrueMotionOnA64BeamStreet) {
  // Scan-to-scan odometry started from the true motion, on scans de-skewed with it: the error left
  // is the registration's own. Plane patches fitted along one scan ring (range noise tilts their
  // normal towards the sensor) once gave a steady pitch bias of about 0.04 deg per scan.
  constexpr int kFrames = 12;
  sim::Simulator simulator =
      test::make_simulator(sim::ScenarioKind::Urban, kFrames, 5, sensor_preset("HDL-64E"));
  PipelineConfig cfg;
  cfg.sensor = simulator.options().sensor;
  ScanToScanOdometry odometry(cfg.odometry);
  double sum_pitch = 0.0, sum_roll = 0.0;
  int n = 0;
  Pose previous = Pose::Identity();
  for (int k = 0; k < kFrames; ++k) {
    const sim::SimFrame f = simulator.frame(k);
    const Pose sweep = simulator.sensor_pose(k, 0.0).inverse() * simulator.sensor_pose(k, 1.0);
    const auto points = deskew(f.scan.cloud.xyz, point_times(f.scan.cloud, true), sweep);
    const auto seg = segment(points, cfg.sensor, cfg.segmentation);
    const auto feat = extract_features(points, seg, cfg.features);
    const Pose truth = previous.inverse() * f.pose;
    const OdometryResult r = odometry.process({feat.f_e, feat.f_p, {}, {}}, feat.F_e, feat.F_p, truth);
    previous = f.pose;
    if (k == 0) continue;
    const Eigen::Matrix3d R = (truth.inverse() * r.motion).rotation();
    sum_pitch += -std::asin(std::clamp(R(2, 0), -1.0, 1.0)) * 180 / M_PI;
    sum_roll += std::atan2(R(2, 1), R(2, 2)) * 180 / M_PI;
    ++n;
  }
  std::printf("mean odometry error per scan over %d scans: pitch %.4f deg, roll %.4f deg\n", n, sum_pitch / n,
              sum_roll / n);
  EXPECT_LT(std::abs(sum_pitch / n), 0.015);
  EXPECT_LT(std::abs(sum_roll / n), 0.015);
}

namespace {
/// The pipeline with the geometric detector over `frames` scans of a highway drive at 90 km/h.
struct HighwayRun {
  std::vector<Pose> est, gt;
  std::size_t moving_static = 0, points = 0;  ///< ground-truth static points labelled moving
};
HighwayRun run_highway(double traffic, int frames, const PipelineConfig& base) {
  // The world of `dloam simulate --scenario highway --frames 100 --seed 2`, its first scans.
  sim::Simulator simulator =
      test::make_simulator(sim::ScenarioKind::Highway, 100, 2, sensor_preset("HDL-64E"), traffic);
  PipelineConfig cfg = base;
  cfg.sensor = simulator.options().sensor;
  cfg.detection.detector = Detector::kGeometric;
  Pipeline pipeline(cfg);
  HighwayRun run;
  for (int k = 0; k < frames; ++k) {
    const sim::SimFrame f = simulator.frame(k);
    const ScanResult r = pipeline.process(f.scan.cloud);
    run.est.push_back(r.pose);
    run.gt.push_back(f.pose);
    for (std::size_t i = 0; k > 0 && i < r.labels.size(); ++i) {
      run.moving_static += semantic::is_moving(r.labels[i]) && !semantic::is_moving(f.scan.labels[i]);
      ++run.points;
    }
  }
  return run;
}

/// The run's end-point error (printed with the drive length).
test::EndPointError reported_end_point_error(const HighwayRun& run) {
  const test::EndPointError e = test::end_point_error(run.est, run.gt);
  std::printf("%zu scans, %.2f m: end-point error %.3f m, %.3f deg\n", run.est.size(),
              e.truth.translation().norm(), e.error.translation().norm(),
              rotation_angle(e.error) * 180 / M_PI);
  return e;
}
}  // namespace

TEST(OdometrySim, FastDriveFlagsNoStaticWallsAsMoving) {
  // At 25 m/s the de-skew moves points by up to 1.25 m: the previous range image must hold each
  // point where its final de-skew puts it (it once kept the pixels of the segmentation's de-skew,
  // and the walls beside the road came out as moving on 30 % of the points).
  const HighwayRun run = run_highway(0.0, 5, PipelineConfig{});
  const double fp = static_cast<double>(run.moving_static) / static_cast<double>(run.points);
  std::printf("static points labelled moving: %.3f %%\n", 100.0 * fp);
  EXPECT_LT(fp, 0.01);
}

TEST(OdometrySim, HeavyCoMovingTrafficOnAHighwayDoesNotPullTheOdometry) {
  // Lanes full of cars at about the ego speed, few poles: a few wrongly registered objects once
  // gave T_coarse jumps of 5 deg, and a 5 m correspondence radius let the odometry lock onto
  // traffic and repeated posts (73 % drift without the detector, 57 % with it).
  const HighwayRun run = run_highway(3.0, 30, PipelineConfig{});
  const auto [err, gt_rel] = reported_end_point_error(run);
  EXPECT_GT(gt_rel.translation().norm(), 50.0);
  EXPECT_LT(err.translation().norm(), 0.01 * gt_rel.translation().norm());
  EXPECT_LT(rotation_angle(err), 0.5 * M_PI / 180.0);
}

TEST(OdometrySim, GuardRailPostsDoNotPullTheOdometryALaneLengthOff) {
  // The whole drive of `dloam simulate --scenario highway --frames 100 --seed 2 --traffic 3`: at its
  // last scan the odometry, started from a T_coarse good to 3 cm, slid 4.2 m back along the
  // guard rails (repeated posts) until it was held to the motion gate around T_coarse.
  const HighwayRun run = run_highway(3.0, 100, PipelineConfig{});
  const auto [err, gt_rel] = reported_end_point_error(run);
  EXPECT_GT(gt_rel.translation().norm(), 240.0);
  EXPECT_LT(err.translation().norm(), 0.005 * gt_rel.translation().norm());
}

TEST(OdometrySim, TheFirstStepIsMeasuredBetweenTwoDeskewedScans) {
  // With the detector, scan 1 is de-skewed with T_coarse before the odometry; its target, the
  // first scan, once was not (it was only after a first estimate). Registering a de-skewed sweep
  // to a skewed one made the first step 2-6 cm short on 64-beam streets at 25 km/h, and the map
  // built on the first scan kept that: t_rel 0.086 % instead of 0.056 % on `urban --seed 11
  // --traffic 3 --frames 200`.
  for (const std::uint64_t seed : {11, 17}) {
    sim::Simulator simulator =
        test::make_simulator(sim::ScenarioKind::Urban, 4, seed, sensor_preset("HDL-64E"), 0.0);
    PipelineConfig cfg;
    cfg.sensor = simulator.options().sensor;
    cfg.detection.detector = Detector::kGeometric;
    Pipeline pipeline(cfg);
    std::vector<Pose> gt;
    for (int k = 0; k < 3; ++k) {
      const sim::SimFrame f = simulator.frame(k);
      pipeline.process(f.scan.cloud);
      gt.push_back(f.pose);
    }
    const std::vector<Pose> est = pipeline.trajectory();
    const Pose err = (est[0].inverse() * est[1]).inverse() * (gt[0].inverse() * gt[1]);
    std::printf("seed %d: first step %.3f m, error %.4f m, %.4f deg\n", static_cast<int>(seed),
                (gt[0].inverse() * gt[1]).translation().norm(), err.translation().norm(),
                rotation_angle(err) * 180 / M_PI);
    EXPECT_LT(err.translation().norm(), 0.01);
    EXPECT_LT(rotation_angle(err), 0.03 * M_PI / 180.0);
  }
}
