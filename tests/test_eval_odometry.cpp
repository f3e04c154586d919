// Odometry metrics against hand-computed cases of the KITTI devkit protocol, ATE and RPE.
#include <gtest/gtest.h>

#include <cmath>

#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/eval/plot.hpp"

using namespace dloam;
using namespace dloam::eval;

namespace {

Pose translation(double x, double y, double z) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, y, z);
  return p;
}

/// n poses along x, `spacing` metres apart, identity rotations.
std::vector<Pose> straight_line(std::size_t n, double spacing) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < n; ++i) poses.push_back(translation(spacing * static_cast<double>(i), 0, 0));
  return poses;
}

/// A curved 3D drive with turning heading (non-collinear positions).
std::vector<Pose> curvy_drive(std::size_t n) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 0.1 * static_cast<double>(i);
    Pose p = Pose::Identity();
    p.linear() = Eigen::AngleAxisd(0.3 * t, Vec3::UnitZ()).toRotationMatrix();
    p.translation() = Vec3(10.0 * std::sin(0.3 * t), 10.0 * (1.0 - std::cos(0.3 * t)), 0.2 * t * t);
    poses.push_back(p);
  }
  return poses;
}

}  // namespace

TEST(EvalRelative, SegmentEndIsFirstFrameStrictlyBeyondLength) {
  const auto dist = trajectory_distances(straight_line(11, 1.0));  // 0, 1, ..., 10 m
  ASSERT_EQ(dist.size(), 11u);
  EXPECT_DOUBLE_EQ(dist.back(), 10.0);
  EXPECT_EQ(last_frame_of_segment(dist, 0, 9.5), std::optional<std::size_t>(10));
  EXPECT_EQ(last_frame_of_segment(dist, 0, 3.0), std::optional<std::size_t>(4));  // devkit: dist > 3, not >=
  EXPECT_FALSE(last_frame_of_segment(dist, 0, 10.0).has_value());
  EXPECT_FALSE(last_frame_of_segment(dist, 1, 9.5).has_value());
}

TEST(EvalRelative, SegmentEnumerationCounts) {
  const auto gt = straight_line(11, 1.0);
  // Length 2.5 ends 3 frames later (starts 0..7), length 5 ends 6 frames later (starts 0..4).
  SegmentOptions every_frame{{2.5, 5.0}, 1};
  const auto all = relative_error(gt, gt, every_frame);
  EXPECT_EQ(all.segments.size(), 8u + 5u);
  ASSERT_EQ(all.per_length.size(), 2u);
  EXPECT_EQ(all.per_length[0].count, 8u);
  EXPECT_EQ(all.per_length[1].count, 5u);
  SegmentOptions every_second{{2.5, 5.0}, 2};  // starts 0,2,4,6 and 0,2,4
  EXPECT_EQ(segment_errors(gt, gt, every_second).size(), 4u + 3u);
  // The devkit default (100..800 m) has no segment on a 10 m path: means are NaN, not 0.
  const auto none = relative_error(gt, gt);
  EXPECT_TRUE(none.segments.empty());
  EXPECT_TRUE(std::isnan(none.t_rel_pct));
  EXPECT_TRUE(none.per_length.empty());
}

TEST(EvalRelative, ScaleErrorGivesTranslationErrorOverNominalLength) {
  const auto gt = straight_line(11, 1.0);
  const auto est = straight_line(11, 1.01);  // 1 % too long
  const auto r = relative_error(gt, est, {{9.5}, 1});
  ASSERT_EQ(r.segments.size(), 1u);
  // Segment 0 -> 10 covers 10 m; the error 0.1 m is divided by the nominal 9.5 m (devkit).
  EXPECT_NEAR(r.t_rel_pct, 100.0 * 0.1 / 9.5, 1e-9);
  EXPECT_NEAR(r.r_rel_deg100m, 0.0, 1e-9);
  // Every segment of a uniformly scaled line has t_err = 1 % * actual / nominal.
  const auto r2 = relative_error(gt, est, {{1.5, 3.5}, 1});  // actual 2 m and 4 m
  ASSERT_EQ(r2.per_length.size(), 2u);
  EXPECT_NEAR(r2.per_length[0].t_rel_pct, 1.0 * 2.0 / 1.5, 1e-9);
  EXPECT_NEAR(r2.per_length[1].t_rel_pct, 1.0 * 4.0 / 3.5, 1e-9);
  EXPECT_EQ(r2.per_length[0].count, 9u);
  EXPECT_EQ(r2.per_length[1].count, 7u);
  EXPECT_NEAR(r2.t_rel_pct, (9 * 2.0 / 1.5 + 7 * 4.0 / 3.5) / 16.0, 1e-9);  // plain mean over segments
}

TEST(EvalRelative, ConstantYawDriftGivesKnownRotationError) {
  const double drift = 0.002;  // rad per frame
  const auto gt = straight_line(21, 1.0);
  auto est = gt;
  for (std::size_t i = 0; i < est.size(); ++i) {
    est[i].linear() = Eigen::AngleAxisd(drift * static_cast<double>(i), Vec3::UnitZ()).toRotationMatrix();
  }
  const auto r = relative_error(gt, est, {{9.5}, 1});
  ASSERT_EQ(r.segments.size(), 11u);  // starts 0..10, each 10 frames long
  for (const auto& s : r.segments) EXPECT_NEAR(s.r_err, 10 * drift / 9.5, 1e-9);
  EXPECT_NEAR(r.r_rel_deg100m, 100.0 * 180.0 / M_PI * 10 * drift / 9.5, 1e-6);
}

TEST(EvalRelative, RejectsBadInput) {
  const auto gt = straight_line(11, 1.0);
  EXPECT_THROW(relative_error(gt, straight_line(10, 1.0)), InputError);
  EXPECT_THROW(relative_error(gt, gt, {{10.0}, 0}), InputError);
  EXPECT_THROW(relative_error(gt, gt, {{-1.0}, 1}), InputError);
  EXPECT_THROW(relative_error(gt, gt, {{5.0, 5.0}, 1}), InputError);
}

TEST(EvalAbsolute, RigidlyMovedCopyHasZeroAlignedAteOnly) {
  const auto gt = curvy_drive(60);
  Pose world = Pose::Identity();
  world.linear() = Eigen::AngleAxisd(0.2, Vec3(0.1, 0.3, 1.0).normalized()).toRotationMatrix();
  world.translation() = Vec3(1.0, -2.0, 0.5);
  std::vector<Pose> est;
  for (const Pose& p : gt) est.push_back(world * p);
  const auto result = evaluate_odometry(gt, est, {{2.0, 4.0}, 1});
  EXPECT_GT(result.ate.rmse, 0.5);
  EXPECT_LT(result.ate_aligned.rmse, 1e-9);
  EXPECT_TRUE(result.alignment.isApprox(world.inverse(), 1e-9));
  // A change of world frame leaves every relative measure unchanged.
  EXPECT_GT(result.relative.segments.size(), 10u);
  EXPECT_NEAR(result.relative.t_rel_pct, 0.0, 1e-9);
  // acos(0.5 (trace - 1)) (devkit formula) resolves angles only down to ~1.5e-8 rad in double.
  EXPECT_NEAR(result.relative.r_rel_deg100m, 0.0, 1e-3);
  EXPECT_NEAR(result.rpe.trans_m.rmse, 0.0, 1e-9);
  EXPECT_EQ(result.frames, 60u);
}

TEST(EvalAbsolute, KnownOffsetAndPerFrameScaleError) {
  const auto gt = straight_line(11, 1.0);
  std::vector<Pose> shifted;
  for (const Pose& p : gt) shifted.push_back(translation(0.3, 0.4, 0.0) * p);
  EXPECT_NEAR(ate(gt, shifted).rmse, 0.5, 1e-12);
  EXPECT_NEAR(ate(gt, shifted).mean, 0.5, 1e-12);
  EXPECT_NEAR(ate_aligned(gt, shifted).rmse, 0.0, 1e-9);

  const auto est = straight_line(11, 1.01);
  const Rpe r = rpe(gt, est);
  EXPECT_EQ(r.trans_m.count, 10u);
  EXPECT_NEAR(r.trans_m.mean, 0.01, 1e-12);
  EXPECT_NEAR(r.trans_m.rmse, 0.01, 1e-12);
  EXPECT_NEAR(r.rot_deg.max, 0.0, 1e-9);
  EXPECT_EQ(r.steps, 10u);
  EXPECT_EQ(r.tracked, 10u);  // 1 cm per step
  // Steps 6 cm too long are not tracked.
  EXPECT_EQ(rpe(gt, straight_line(11, 1.06)).tracked, 0u);
  // Unaligned ATE of the scaled line: errors 0.01 * i for i = 0..10.
  double sum_sq = 0.0;
  for (int i = 0; i <= 10; ++i) sum_sq += 1e-4 * i * i;
  EXPECT_NEAR(ate(gt, est).rmse, std::sqrt(sum_sq / 11.0), 1e-12);
  EXPECT_THROW(evaluate_odometry(gt, straight_line(12, 1.0)), InputError);
  EXPECT_THROW(evaluate_odometry({}, {}), InputError);
}

TEST(EvalPlot, ScriptEmbedsDataAndRejectsBadAxes) {
  const auto gt = straight_line(5, 1.0);
  const auto est = straight_line(5, 1.01);
  const auto r = relative_error(gt, est, {{1.5}, 1});
  PlotOptions options;
  options.png_path = "/tmp/it's.png";
  const std::string script = odometry_plot_script(gt, est, r.per_length, options);
  EXPECT_NE(script.find("$gt << EOD\n0 0\n1 0\n"), std::string::npos);
  EXPECT_NE(script.find("4.04 0\nEOD"), std::string::npos);
  EXPECT_NE(script.find("set output '/tmp/it''s.png'"), std::string::npos);
  EXPECT_NE(script.find("set terminal pngcairo"), std::string::npos);
  options.vertical_axis = 0;
  EXPECT_THROW(odometry_plot_script(gt, est, r.per_length, options), InputError);
}

TEST(EvalRelative, FileWithItselfIsExactEvenIfRotationsAreSlightlyNonOrthonormal) {
  auto poses = curvy_drive(40);
  for (Pose& p : poses) p.linear() *= 1.0 - 4e-8;  // like 10-digit KITTI files: |R^T R - I| ~ 1e-7
  const auto r = evaluate_odometry(poses, poses, {{1.0, 2.0}, 1});
  ASSERT_GT(r.relative.segments.size(), 20u);
  // A transposing inverse would leave acos(1 - 1.2e-7) ~ 5e-4 rad per segment here.
  for (const auto& s : r.relative.segments) EXPECT_LT(s.r_err * s.length, 1e-6);
  EXPECT_LT(r.rpe.rot_deg.max, 1e-4);
}
