// Simulator paths with clothoid corner transitions: continuous position, heading and curvature
// (the yaw rate ramps instead of jumping), arc-length parametrisation, closed loops that close,
// and offset / reversed curves of spirals.
#include <gtest/gtest.h>

#include <cmath>

#include "dloam/sim/path.hpp"

using namespace dloam::sim;

namespace {
/// Signed heading change per metre between s - h and s + h.
double curvature_at(const Path& p, double s, double h = 0.05) {
  return std::remainder(p.at(s + h).yaw - p.at(s - h).yaw, 2.0 * M_PI) / (2.0 * h);
}
}  // namespace

TEST(SimPathTransitions, CurvatureRampsAndTheLoopCloses) {
  const double radius = 10.0, transition = 12.0;
  const Path p = Path::from_waypoints({{0, 0}, {100, 0}, {100, 80}, {0, 80}}, radius, true, transition);
  double prev_yaw = p.at(0.0).yaw, max_curvature = 0.0, max_dcurvature = 0.0, prev_k = 0.0;
  const double ds = 0.02;
  for (double s = ds; s < p.length(); s += ds) {
    const PathPoint a = p.at(s - ds), b = p.at(s);
    ASSERT_NEAR((b.p - a.p).norm(), ds, 1e-6) << s;  // arc length, no jumps
    ASSERT_LT(std::abs(std::remainder(b.yaw - prev_yaw, 2.0 * M_PI)), ds / radius + 1e-6) << s;
    prev_yaw = b.yaw;
    const double k = curvature_at(p, s);
    max_curvature = std::max(max_curvature, std::abs(k));
    max_dcurvature = std::max(max_dcurvature, std::abs(k - prev_k) / ds);
    prev_k = k;
  }
  EXPECT_NEAR(max_curvature, 1.0 / radius, 1e-3);
  // The curvature changes by at most 1 / (r l) per metre (a line-arc corner jumps by 1 / r at once).
  EXPECT_LT(max_dcurvature, 1.05 / (radius * transition));
  EXPECT_NEAR((p.at(p.length()).p - p.at(0.0).p).norm(), 0.0, 1e-6);
  EXPECT_NEAR(std::remainder(p.at(p.length()).yaw - p.at(0.0).yaw, 2.0 * M_PI), 0.0, 1e-9);
  // Each 90 degree corner still turns by exactly 90 degrees: heading on the next leg.
  EXPECT_NEAR(std::remainder(p.at(p.length() * 0.4).yaw, 2.0 * M_PI), M_PI / 2.0, 1e-9);
}

TEST(SimPathTransitions, OffsetAndReversedSpiralsStayParallel) {
  const Path p = Path::from_waypoints({{0, 0}, {100, 0}, {160, 60}, {160, 200}}, 20.0, false, 15.0);
  const Path right = p.offset(-3.0), back = p.reversed();
  EXPECT_NEAR(back.length(), p.length(), 1e-9);
  for (double s = 0.0; s <= p.length(); s += 1.0) {
    const PathPoint a = p.at(s), r = back.at(p.length() - s);
    EXPECT_NEAR((a.p - r.p).norm(), 0.0, 1e-6) << s;
    EXPECT_NEAR(std::abs(std::remainder(a.yaw - r.yaw, 2.0 * M_PI)), M_PI, 1e-6) << s;
  }
  for (double s = 0.0; s <= right.length(); s += 2.5) {
    double best = 1e9;
    for (double u = 0.0; u <= p.length(); u += 0.01)
      best = std::min(best, (p.at(u).p - right.at(s).p).norm());
    EXPECT_NEAR(best, 3.0, 1e-3) << s;
  }
  const double ds = 0.02;  // the offset curve is arc-length parametrised too
  for (double s = ds; s < right.length(); s += 0.37)
    EXPECT_NEAR((right.at(s).p - right.at(s - ds).p).norm(), ds, 1e-5) << s;
  // Offsetting the reversed curve to its left = the right offset of the original, reversed.
  const Path back_left = back.offset(3.0);
  for (double s = 0.0; s <= right.length(); s += 5.0)
    EXPECT_NEAR((back_left.at(right.length() - s).p - right.at(s).p).norm(), 0.0, 1e-6) << s;
}

TEST(SimPathTransitions, ShortLegsShrinkTheCornerAndZeroTransitionIsAnArc) {
  // 10 m legs cannot hold a 20 m radius corner with 15 m spirals: everything shrinks, still smooth.
  const Path small = Path::from_waypoints({{0, 0}, {10, 0}, {10, 10}}, 20.0, false, 15.0);
  const double ds = 0.01;
  for (double s = ds; s < small.length(); s += ds)
    ASSERT_NEAR((small.at(s).p - small.at(s - ds).p).norm(), ds, 1e-6) << s;
  EXPECT_NEAR((small.at(small.length()).p - Eigen::Vector2d(10, 10)).norm(), 0.0, 1e-6);
  const Path arc = Path::from_waypoints({{0, 0}, {50, 0}, {50, 30}}, 8.0, false, 0.0);
  EXPECT_NEAR(arc.length(), 80.0 - (2.0 * 8.0 - 8.0 * M_PI / 2.0), 1e-9);
}
