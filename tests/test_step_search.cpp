// The step search without a trusted prior: its candidate grid follows the platform's reach over the
// interval, and stays bounded when scans were dropped for seconds.
#include <gtest/gtest.h>

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
