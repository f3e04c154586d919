#include "dloam/core/motion_model.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace dloam {

namespace {
constexpr double kDeg = M_PI / 180.0;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}
}  // namespace

std::vector<std::string> motion_platform_names() { return {"car", "handheld", "legged"}; }

MotionConfig motion_preset(const std::string& platform) {
  MotionConfig c;  // car: hard braking (~8 m/s^2) and swerves (~30 deg/s) stay far inside its gates
  const std::string p = lower(platform);
  if (p == "car") return c;
  if (p == "handheld") {
    // A person walking with the sensor: quick looks around (up to 360 deg/s), turns that start
    // and stop within a tenth of a second, steps and bumps.
    c.platform = "handheld";
    c.max_speed = 5.0;
    c.max_angular_speed_deg = 360.0;
    c.max_acceleration = 10.0;
    c.max_angular_acceleration_deg = 1000.0;
    c.step_noise = 0.05;
    return c;
  }
  if (p == "legged") {
    // A quadruped: trotting pitch/roll oscillation, turns on the spot.
    c.platform = "legged";
    c.max_speed = 5.0;
    c.max_angular_speed_deg = 180.0;
    c.max_acceleration = 10.0;
    c.max_angular_acceleration_deg = 600.0;
    c.step_noise = 0.05;
    return c;
  }
  std::string known;
  for (const auto& n : motion_platform_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown platform '" + platform + "' (known: " + known + ")");
}

Pose MotionModel::predict(double dt) const {
  if (!known_) return Pose::Identity();
  Vec6 twist = twist_;
  // From the middle of the last step to the middle of this one.
  if (config_.turn_acceleration) twist(2) += yaw_rate_change_ * 0.5 * (dt_last_ + dt);
  return exp_se3(dt * twist);
}

MotionGate MotionModel::gate(double dt) const {
  // The velocity of the last step is its mean over that interval, the next step's over this one:
  // between their middles the velocity changes by at most a * (dt_last + dt) / 2.
  const double span = dt * 0.5 * (dt + (known_ ? dt_last_ : dt));
  return {config_.max_acceleration * span + config_.step_noise,
          (config_.max_angular_acceleration_deg * span + config_.step_noise_deg) * kDeg};
}

void MotionModel::update(const Pose& step, double dt) {
  if (!(dt > 0.0))
    throw std::invalid_argument("MotionModel::update: the time between scans must be positive");
  const Vec6 twist = log_se3(step) / dt;
  if (known_) {
    const double change = (twist(2) - twist_(2)) / (0.5 * (dt_last_ + dt));
    const double limit = config_.max_angular_acceleration_deg * kDeg;
    yaw_rate_change_ = std::clamp(change, -limit, limit);
  }
  twist_ = twist;
  dt_last_ = dt;
  known_ = true;
}

}  // namespace dloam
