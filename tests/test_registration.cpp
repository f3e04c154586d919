// Registration, de-skew and SE(3) algebra on synthetic geometry with known answers.
#include <gtest/gtest.h>

#include <random>

#include "dloam/core/degeneracy.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/registration.hpp"
#include "dloam/core/se3.hpp"
#include "pose_test_util.hpp"

using namespace dloam;

namespace {

using test::make_pose;

/// A "street corner": ground plane, two perpendicular walls, and vertical poles (edges).
struct Scene {
  std::vector<Vec3> edges, planes;
};

Scene make_scene(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.005);
  Scene s;
  for (int i = 0; i < 3000; ++i)
    s.planes.emplace_back(20 * u(rng), 20 * u(rng), -1.8 + noise(rng));  // ground
  for (int i = 0; i < 1500; ++i)
    s.planes.emplace_back(12 + noise(rng), 20 * u(rng), 2 * u(rng));  // wall x=12
  for (int i = 0; i < 1500; ++i)
    s.planes.emplace_back(20 * u(rng), -9 + noise(rng), 2 * u(rng));  // wall y=-9
  for (int i = 0; i < 1500; ++i)
    s.planes.emplace_back(-15 + noise(rng), 20 * u(rng), 2 * u(rng));  // wall x=-15
  const Vec3 poles[] = {{5, 5, 0}, {-6, 4, 0}, {3, -6, 0}, {-4, -5, 0}, {9, 2, 0}, {-10, -2, 0}};
  for (const auto& p : poles)
    for (int i = 0; i < 60; ++i)
      s.edges.emplace_back(p.x() + noise(rng), p.y() + noise(rng), -1.8 + 4.0 * (i / 60.0));
  return s;
}

std::vector<Vec3> transformed(const Pose& T, const std::vector<Vec3>& pts) {
  std::vector<Vec3> out;
  for (const auto& p : pts) out.push_back(T * p);
  return out;
}

}  // namespace

TEST(Se3, ExpLogRoundTripAndInterpolation) {
  const Pose T = make_pose(0.1, -0.05, 0.7, {1.0, -2.0, 0.3});
  const Pose back = exp_se3(log_se3(T));
  EXPECT_TRUE(back.isApprox(T, 1e-12));
  const Pose half = scale_motion(T, 0.5);
  EXPECT_TRUE((half * half).isApprox(T, 1e-12));
  EXPECT_TRUE(scale_motion(T, 0.0).isApprox(Pose::Identity(), 1e-12));
}

TEST(Registration, RecoversKnownMotionWithAllDof) {
  std::mt19937 rng(1);
  const Scene s = make_scene(rng);
  FeatureMap target;
  target.edges.build(s.edges);
  target.planes.build(s.planes);
  const Pose truth = make_pose(0.02, -0.015, 0.08, {0.6, -0.3, 0.05});  // source -> target
  FeatureSource src{transformed(truth.inverse(), s.edges), transformed(truth.inverse(), s.planes), {}, {}};
  RegistrationParams p;
  p.max_iterations = 30;
  const auto r = register_features(src, target, Pose::Identity(), p);
  const Pose err = r.T.inverse() * truth;
  EXPECT_LT(err.translation().norm(), 0.01);
  EXPECT_LT(rotation_angle(err), 0.001);
  EXPECT_GT(r.plane_matches, 5000);
  EXPECT_GT(r.edge_matches, 300);
  EXPECT_FALSE(r.degenerate());
}

TEST(Registration, TwoStepDofMasksOnlyMoveTheirOwnDegreesOfFreedom) {
  std::mt19937 rng(2);
  const Scene s = make_scene(rng);
  FeatureMap target;
  target.edges.build(s.edges);
  target.planes.build(s.planes);
  const Pose truth = make_pose(0.01, 0.01, 0.05, {0.4, 0.2, 0.06});
  FeatureSource planes{{}, transformed(truth.inverse(), s.planes), {}, {}};
  RegistrationParams p;
  // The masks alone: six poles within 10 m give yaw about 30 features' worth (rotations counted
  // at 20 m), which the default thresholds, set for whole scans, would keep at the prior.
  p.degeneracy.min_features = 5.0;
  p.degeneracy.min_fraction = 0.0;
  p.dof = kPlaneStepDof;
  const auto step1 = register_features(planes, target, Pose::Identity(), p);
  // Only roll, pitch, tz are estimated in step 1: yaw, x, y stay (up to the second-order effect
  // of composing roll/pitch updates) where they started, far from the true 0.05 rad, 0.4 m, 0.2 m.
  const Vec6 xi = log_se3(step1.T);
  EXPECT_LT(std::abs(xi(2)), 1e-4);
  EXPECT_LT(std::abs(step1.T.translation().x()), 0.01);
  EXPECT_LT(std::abs(step1.T.translation().y()), 0.01);
  EXPECT_NEAR(step1.T.translation().z(), truth.translation().z(), 0.02);
  FeatureSource both{transformed(truth.inverse(), s.edges), {}, {}, {}};
  p.dof = kEdgeStepDof;
  const auto step2 = register_features(both, target, step1.T, p);
  const Pose err = step2.T.inverse() * truth;
  EXPECT_LT(err.translation().norm(), 0.05);
  EXPECT_LT(rotation_angle(err), 0.005);
}

TEST(Registration, DegenerateCorridorDoesNotDiverge) {
  // Ground and two parallel walls along x: translation along x is unconstrained.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> planes;
  for (int i = 0; i < 3000; ++i) planes.emplace_back(30 * u(rng), 4 * u(rng), -1.8);
  for (int i = 0; i < 2000; ++i) planes.emplace_back(30 * u(rng), 4.0, 2 * u(rng));
  for (int i = 0; i < 2000; ++i) planes.emplace_back(30 * u(rng), -4.0, 2 * u(rng));
  FeatureMap target;
  target.planes.build(planes);
  const Pose truth = make_pose(0, 0, 0.02, {0.5, 0.1, 0.0});
  FeatureSource src{{}, transformed(truth.inverse(), planes), {}, {}};
  RegistrationParams p;
  const auto r = register_features(src, target, Pose::Identity(), p);
  EXPECT_TRUE(r.degenerate());
  EXPECT_LT(std::abs(r.T.translation().x()), 0.5 + 1e-6);  // no runaway along the corridor
  EXPECT_NEAR(r.T.translation().y(), 0.1, 0.02);           // constrained directions still solved
}

TEST(Degeneracy, AnUnconstrainedDirectionKeepsThePriorOnlyWhereThePriorCanBeTrusted) {
  // A normal matrix (twist coordinates, rad and m) with roll and x far below min_features (30
  // features' worth at rotation_radius 20 m) and the other directions well constrained.
  Mat6 H = Mat6::Identity() * 1e5;
  H(0, 0) = 400.0 * 2.0;  // roll: 2 features' worth at 20 m
  H(3, 3) = 5.0;          // x: 5 features' worth
  const DegeneracyConfig config;
  const double deg = M_PI / 180.0;

  // No prior error given: both weak directions keep the prior.
  const Degeneracy exact = analyse_degeneracy(H, 1000, kAllDof, config);
  EXPECT_EQ(exact.unconstrained, 2);
  EXPECT_EQ(exact.held, 2);
  EXPECT_EQ(unconstrained_names(exact), "roll+x");

  // A car's gate over 0.1 s (1 deg: 0.35 m at 20 m; 0.3 m): both held.
  const Degeneracy car = analyse_degeneracy(H, 1000, kAllDof, config, {1.0 * deg, 0.3});
  EXPECT_EQ(car.unconstrained, 2);
  EXPECT_EQ(car.held, 2);
  EXPECT_TRUE(car.keeps_prior());

  // A handheld scanner's gate (10.5 deg: 3.7 m at 20 m; 0.15 m): x is held, roll is estimated.
  const Degeneracy handheld = analyse_degeneracy(H, 1000, kAllDof, config, {10.5 * deg, 0.15});
  EXPECT_TRUE(handheld.degenerate());
  EXPECT_EQ(handheld.unconstrained, 2);
  ASSERT_EQ(handheld.held, 1);
  EXPECT_EQ(direction_name(handheld.eigenvectors.col(0)), "x");  // the held ones come first
  EXPECT_EQ(direction_name(handheld.eigenvectors.col(1)), "roll");

  // Neither can be trusted: the degeneracy is reported, nothing keeps the prior.
  const Degeneracy loose = analyse_degeneracy(H, 1000, kAllDof, config, {10.5 * deg, 1.5});
  EXPECT_EQ(loose.unconstrained, 2);
  EXPECT_EQ(loose.held, 0);
  EXPECT_FALSE(loose.keeps_prior());
}

TEST(Deskew, UndoesConstantMotionDuringTheSweep) {
  // A sensor moving 1 m per sweep along x observes static points; each point is measured in the
  // sensor frame at its own time. De-skew maps all of them into the mid-sweep frame.
  const Pose motion = make_pose(0, 0, 0.05, {1.0, 0.0, 0.0});
  std::vector<Vec3> world, measured;
  std::vector<double> times;
  for (int i = 0; i < 200; ++i) {
    const double t = (i + 0.5) / 200.0;
    const Vec3 p(10 * std::cos(i * 0.1), 10 * std::sin(i * 0.1), 0.5);  // world = mid-sweep frame
    const Pose sensor_at_t = scale_motion(motion, t - 0.5);
    world.push_back(p);
    measured.push_back(sensor_at_t.inverse() * p);
    times.push_back(t);
  }
  const auto fixed = deskew(measured, times, motion, 0.5, 4096);
  double worst = 0, before = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    worst = std::max(worst, (fixed[i] - world[i]).norm());
    before = std::max(before, (measured[i] - world[i]).norm());
  }
  EXPECT_GT(before, 0.4);
  EXPECT_LT(worst, 0.01);
}

TEST(Deskew, OfSomePointsEqualsTheWholeScansDeskewAtThem) {
  // The features of a scan are de-skewed again when a better motion arrives: each must land where
  // the whole scan's de-skew puts that point (same time slices), a turn and an acceleration included.
  SweepMotion motion(make_pose(0.02, -0.01, 0.3, {1.2, 0.3, 0.05}));
  motion.acceleration << 0.0, 0.0, 0.2, 0.5, 0.0, 0.0;
  std::vector<Vec3> points;
  std::vector<double> times;
  for (int i = 0; i < 5000; ++i) {
    points.emplace_back(20 * std::cos(i * 0.37), 15 * std::sin(i * 0.11), 0.01 * (i % 300) - 1.5);
    times.push_back(std::fmod(i * 0.6180339887, 1.0));
  }
  const std::vector<int> some = {0, 7, 123, 2500, 4999, 1000, 3};
  for (const int bins : {256, 16}) {
    const std::vector<Vec3> all = deskew(points, times, motion, 0.5, bins);
    const std::vector<Vec3> part = deskew(points, times, some, motion, 0.5, bins);
    ASSERT_EQ(part.size(), some.size());
    for (std::size_t j = 0; j < some.size(); ++j)
      EXPECT_EQ(part[j], all[static_cast<std::size_t>(some[j])])
          << "point " << some[j] << ", " << bins << " bins";
  }
}

TEST(Registration, AnEdgesNeighboursAreALineOnlyWhenTheySpreadAlongItEnoughMoreThanAcross) {
  // Five target edges 0.4 m tall along z; across (x) they are scattered or nearly aligned.
  auto build = [](FeatureMap& target, double across) {
    target.edges.build(
        {{-across, 5, -0.2}, {across, 5, -0.1}, {0, 5, 0.0}, {across, 5, 0.1}, {-across, 5, 0.2}});
    target.planes.build({});
  };
  const FeatureSource src{{{0.0, 5.0, 0.05}}, {}, {}, {}};
  RegistrationParams p;
  p.dof = {false, false, false, false, false, false};  // evaluate only
  // Variance along 0.02 m^2; across 0.0045 (ratio 4.4) when scattered, 0.00008 (ratio 250) when aligned.
  FeatureMap scattered, aligned;
  build(scattered, 0.075);
  build(aligned, 0.01);
  for (const double ratio : {3.0, 10.0}) {
    p.min_line_ratio = ratio;
    EXPECT_EQ(register_features(src, scattered, Pose::Identity(), p).edge_matches, ratio < 4.4 ? 1 : 0)
        << ratio;
    EXPECT_EQ(register_features(src, aligned, Pose::Identity(), p).edge_matches, 1) << ratio;
  }
}
