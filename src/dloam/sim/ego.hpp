// The ego platform, whose motion gives the sensor pose at every instant (the rolling shutter
// fires each column from the pose at its own time). By default it is a car on its path: position
// and heading from the path at the distance of its speed profile, pitch and roll from the terrain
// slope. A BodyMotion adds what other platforms do:
//   - lane-change swerves: a lateral offset from the path (the heading follows the velocity);
//   - an own heading (a person or a legged robot turning on the spot, looking around; a sensor on
//     a turntable) integrated from a yaw-rate profile with bounded angular acceleration;
//   - body oscillations: pitch, roll and vertical bob at the step frequency, scaled by a gait
//     envelope that fades them in and out with the walking speed, and slow tilts;
//   - steps up and down curbs spread over a stride instead of at once.
// The sensor orientation is R = Rz(heading) * [terrain tilt] * Ry(pitch) * Rx(roll): pitch > 0
// turns the nose (x) down, roll > 0 lifts the left side (y).
#pragma once

#include <vector>

#include "dloam/sim/ground.hpp"
#include "dloam/sim/path.hpp"

namespace dloam::sim {

/// A lane change of `shift` metres to the left (negative: right) from t0 over `duration` s, with
/// the sinusoidal lateral acceleration of the standard lane-change manoeuvre:
/// offset = shift (u - sin(2 pi u) / (2 pi)), u = (t - t0) / duration; peak lateral acceleration
/// 2 pi |shift| / duration^2; offset, rate and acceleration are continuous.
struct LaneShift {
  double t0 = 0.0, duration = 1.0, shift = 0.0;
  [[nodiscard]] double offset(double t) const;
  [[nodiscard]] double rate(double t) const;
  [[nodiscard]] double accel(double t) const;
};

/// amplitude * sin(2 pi frequency_hz t + phase).
struct Wave {
  double amplitude = 0.0, frequency_hz = 0.0, phase = 0.0;
  [[nodiscard]] double at(double t) const;
};

struct BodyMotion {
  bool enabled = false;      ///< false: the plain car (the pose of earlier versions, bit for bit)
  bool own_heading = false;  ///< heading = yaw0 + yaw.value(t) instead of the path's heading
  double yaw0 = 0.0;
  RateProfile yaw;                ///< yaw rate (rad/s): own heading, or added to the path's heading
  std::vector<LaneShift> shifts;  ///< lateral offset (left of the path) = sum of the shifts
  bool terrain_tilt = true;       ///< vehicles tilt with the terrain; walkers and turntables stay level
  double step_length = 0.0;       ///< > 0: curbs are stepped up/down over this length (m)
  std::vector<Wave> pitch, roll;  ///< slow tilts (rad), always on
  std::vector<Wave> gait_pitch, gait_roll, gait_bob;  ///< rad, rad, m; times the gait envelope
  double gait_speed = 1.0;  ///< speed (m/s) from which the gait oscillations have full amplitude
};

/// The ego vehicle: follows `path` from arc length s0 with `profile`; the LiDAR sits
/// `mount_height` above the ground (KITTI: 1.73 m), x forward, z up.
struct Ego {
  Path path;
  SpeedProfile profile;
  double s0 = 0.0;
  double mount_height = 1.73;
  BodyMotion body;

  /// Sensor -> world at absolute time t (s).
  [[nodiscard]] Pose sensor_pose(const Ground& ground, double t) const;
  /// Ground-plane position at time t (path point plus lateral offset).
  [[nodiscard]] Vec2 position(double t) const;
  /// Lateral offset (m, left of the path) and its rate (m/s).
  [[nodiscard]] double lateral_offset(double t) const;
  [[nodiscard]] double lateral_rate(double t) const;
  /// Gait envelope in [0, 1]: smoothstep of speed / body.gait_speed (continuous rate of change
  /// wherever the speed profile's slope changes at standstill or at or above gait_speed).
  [[nodiscard]] double gait(double t) const;
};

}  // namespace dloam::sim
