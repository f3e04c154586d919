// The motion prior: constant velocity, and for platforms that turn fast a turn rate that keeps
// changing as it did between the last two steps.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dloam/core/motion_model.hpp"
#include "dloam/core/se3.hpp"

using namespace dloam;

namespace {
constexpr double kDeg = M_PI / 180.0;

/// A step over dt turning `yaw_deg` about z while moving `forward` m along x.
Pose step(double yaw_deg, double forward) {
  Vec6 xi = Vec6::Zero();
  xi(2) = yaw_deg * kDeg;
  xi(3) = forward;
  return exp_se3(xi);
}

double yaw_deg(const Pose& p) { return log_se3(p)(2) / kDeg; }
}  // namespace

TEST(MotionModel, ATurnThatSpeedsUpIsPredictedToGoOnSpeedingUp) {
  MotionConfig config = motion_preset("handheld");
  config.turn_acceleration = true;
  MotionModel model(config);
  // 400 deg/s^2 at 10 Hz: steps of 4, 8 deg; the next is 12.
  model.update(step(4.0, 0.1), 0.1);
  EXPECT_NEAR(yaw_deg(model.predict(0.1)), 4.0, 1e-9);  // one step: no change known yet
  model.update(step(8.0, 0.1), 0.1);
  EXPECT_NEAR(yaw_deg(model.predict(0.1)), 12.0, 1e-9);
  // Translation stays at constant velocity.
  EXPECT_NEAR(log_se3(model.predict(0.1))(3), 0.1, 1e-9);
  // Over a longer interval (a dropped scan) the change goes on to the middle of that interval:
  // 80 deg/s + 400 deg/s^2 * 0.15 s = 140 deg/s for 0.2 s.
  EXPECT_NEAR(yaw_deg(model.predict(0.2)), 28.0, 1e-9);
  // A turn that stops: the change is bounded by what the platform can do (1000 deg/s^2).
  model.update(step(-20.0, 0.1), 0.1);
  EXPECT_NEAR(yaw_deg(model.predict(0.1)), -20.0 - 10.0, 1e-9);
  // Forgotten with the velocity.
  model.reset();
  model.update(step(5.0, 0.0), 0.1);
  EXPECT_NEAR(yaw_deg(model.predict(0.1)), 5.0, 1e-9);
}

TEST(MotionModel, EveryPlatformKeepsItsTurnRateByDefault) {
  for (const std::string& platform : motion_platform_names())
    EXPECT_FALSE(motion_preset(platform).turn_acceleration) << platform;
  MotionModel model(motion_preset("car"));
  EXPECT_FALSE(model.config().turn_acceleration);
  model.update(step(1.0, 1.0), 0.1);
  model.update(step(2.0, 1.0), 0.1);
  EXPECT_NEAR(yaw_deg(model.predict(0.1)), 2.0, 1e-9);
}
