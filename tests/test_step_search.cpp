// The step search without a trusted prior: its candidate grid follows the platform's reach over the
// interval, and stays bounded when scans were dropped for seconds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dloam/core/step_search.hpp"

using namespace dloam;

namespace {
/// Walls and a floor around the origin, as the previous scan's features.
FeatureSource room() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  FeatureSource s;
  for (int i = 0; i < 600; ++i) {
    s.planes.emplace_back(u(rng), u(rng), -1.8);
    s.planes.emplace_back(20.0, u(rng), 0.1 * u(rng));
    s.planes.emplace_back(u(rng), -15.0, 0.1 * u(rng));
  }
  return s;
}
}  // namespace

TEST(StepSearch, ALongIntervalSearchesABoundedGrid) {
  const FeatureSource source = room();
  FeatureMap target;
  target.planes.build(source.planes);
  // A score that prefers standing still: any candidate grid finds the identity.
  const StepScore score = [](const Pose& T, double) {
    return 1.0 / (1.0 + T.translation().norm() + std::abs(std::atan2(T.linear()(1, 0), T.linear()(0, 0))));
  };
  StepSearchOptions options;  // 2 m and 10 deg between candidates, 1000 at most
  options.max_translation = 4.0;
  options.max_rotation = 0.16;
  const StepSearchResult near = search_step(source, target, {Pose::Identity()}, options, score);
  EXPECT_EQ(near.candidates, 5u);  // -4..4 m by 2 m, one yaw: the grid as asked
  EXPECT_LT(near.T.translation().norm(), 0.05);

  // 4 s of dropped scans at 40 m/s and 60 deg/s: 165 travel x 37 yaw candidates at those steps.
  options.max_translation = 164.0;
  options.max_rotation = M_PI;
  const StepSearchResult far = search_step(source, target, {Pose::Identity()}, options, score);
  EXPECT_GT(far.candidates, 100u);
  EXPECT_LE(far.candidates, options.max_candidates);
  EXPECT_LT(far.T.translation().norm(), 0.05);
}

TEST(StepSearch, ANearlyRightCentreIsNotPulledOntoAnObjectThatMoved) {
  // The previous scan: the room and the back of a vehicle; the current one: the same room, the
  // vehicle 1.5 m further along x (it drove on). The sensor stood still.
  FeatureSource source = room();
  const std::size_t static_points = source.planes.size();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> vehicle;
  for (int i = 0; i < 1500; ++i)
    vehicle.emplace_back(6.0, 2.0 + 2.0 * u(rng), -1.5 + 1.5 * u(rng));  // its back, facing the sensor
  std::vector<Vec3> previous = source.planes;
  for (const Vec3& p : vehicle) {
    previous.push_back(p);
    source.planes.push_back(p + Vec3(1.5, 0.0, 0.0));
  }
  FeatureMap target;
  target.planes.build(previous);
  // The caller's score: how close the static points come back onto themselves (1: exactly).
  const StepScore score = [&](const Pose& T, double tolerance) {
    double sum = 0.0;
    for (std::size_t i = 0; i < static_points; ++i)
      sum += std::max(0.0, 1.0 - (T * source.planes[i] - source.planes[i]).norm() / tolerance);
    return sum / static_cast<double>(static_points);
  };
  StepSearchOptions options;
  options.max_translation = 2.0;
  options.max_rotation = 0.0;
  const Pose centre = Pose(Eigen::Translation3d(0.05, 0.0, 0.0));  // the prediction, 5 cm off
  const StepSearchResult r = search_step(source, target, {centre}, options, score);
  EXPECT_LT(r.T.translation().norm(), 0.03);
  EXPECT_GT(r.fitness, 0.85);
}
