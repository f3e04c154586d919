// The odometry's motion prior in physical units: the sensor's velocity (a twist per second, from
// the last estimated step and the time it took) predicts the next step over the actual time
// between the two scans, and a gate bounds how far an estimate may depart from that prediction:
// what the platform's accelerations allow over that time. Scans 0.3 s apart (a driver that
// dropped two) get a prediction three times as long and a gate that grows with the square of the
// interval; a handheld scanner gets the turn rates a wrist makes.
#pragma once

#include <string>
#include <vector>

#include "dloam/core/se3.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// What the platform can do, in physical units (`motion:` section; `platform` picks the defaults).
struct MotionConfig {
  /// car | handheld | legged: the defaults of the fields below (motion_preset); keys given beside
  /// it override them.
  std::string platform = "car";
  double max_speed = 40.0;              ///< m/s: fastest the sensor moves (a step searched with no prior)
  double max_angular_speed_deg = 60.0;  ///< deg/s: fastest it turns (a car's swerve: about 30)
  double max_acceleration = 20.0;       ///< m/s^2: change of velocity the prior allows (hard braking ~8)
  double max_angular_acceleration_deg = 50.0;  ///< deg/s^2: change of turn rate the prior allows
  /// Estimation noise of a step (m, deg) that the gate admits on top of the accelerations: the
  /// previous step's own error carries into the prediction.
  double step_noise = 0.1;
  double step_noise_deg = 0.5;
  /// Check each prediction against the previous scan and search the step without it when the
  /// data contradicts it (and the first step, without a detector); off: always trust it.
  bool step_search = true;
  /// Predict the turn rate about the sensor's z axis at constant angular acceleration: its change
  /// between the last two steps goes on (at most max_angular_acceleration_deg). A turn on the spot
  /// from standing speeds up over several scans, and at constant turn rate each of those steps is
  /// predicted short by the whole change. Off on every platform: where turns reverse within a scan
  /// or two (a walker looking around, a trotting robot), the extrapolation overshoots by twice the
  /// change, and simulated walks lost track more often with it (docs/tracking.md). Pitch, roll and
  /// translation stay at constant velocity.
  bool turn_acceleration = false;
};

/// The built-in platforms: car, handheld, legged.
std::vector<std::string> motion_platform_names();
/// A platform's defaults (case-insensitive); throws std::invalid_argument if unknown.
MotionConfig motion_preset(const std::string& platform);

/// The largest departure of an estimated step from its prediction that the platform can make.
struct MotionGate {
  double max_translation = 0.0;  ///< m
  double max_rotation = 0.0;     ///< rad
  /// Whether `change` (prediction^-1 * estimate) stays within the gate.
  [[nodiscard]] bool admits(const Pose& change) const {
    return translation_norm(change) <= max_translation && rotation_angle(change) <= max_rotation;
  }
};

class MotionModel {
 public:
  explicit MotionModel(const MotionConfig& config) : config_(config) {}

  /// The motion (scan frame -> previous scan frame) expected over `dt` seconds: the last velocity
  /// held constant (with turn_acceleration, the turn rate changing as between the last two steps);
  /// identity before the first step.
  [[nodiscard]] Pose predict(double dt) const;
  /// How far a step over `dt` may depart from predict(dt): the acceleration limits over the
  /// interval (a * dt * (dt + dt_last) / 2, the velocity change over half of each interval) plus
  /// the step noise.
  [[nodiscard]] MotionGate gate(double dt) const;
  /// The step just estimated over `dt` seconds becomes the velocity.
  void update(const Pose& step, double dt);
  /// Forgets the velocity (the next step is predicted as standing still, with no gate history).
  void reset() {
    known_ = false;
    yaw_rate_change_ = 0.0;
  }
  [[nodiscard]] bool known() const { return known_; }
  /// The velocity [wx, wy, wz, vx, vy, vz] (rad/s, m/s) in the sensor frame.
  [[nodiscard]] const Vec6& twist() const { return twist_; }
  /// The time (s) over which twist() was measured (0 before the first step).
  [[nodiscard]] double twist_dt() const { return known_ ? dt_last_ : 0.0; }
  [[nodiscard]] const MotionConfig& config() const { return config_; }

 private:
  MotionConfig config_;
  Vec6 twist_ = Vec6::Zero();
  double dt_last_ = 0.0;
  bool known_ = false;
  /// rad/s^2 about the sensor's z between the middles of the last two steps (0 before the second)
  double yaw_rate_change_ = 0.0;
};

}  // namespace dloam
