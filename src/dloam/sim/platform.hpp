// Motions of the ego platforms beyond a car cruising along its path:
//   - handheld: a person walking a street's sidewalk with the sensor at about 1.5 m (legs of
//     1-1.5 m/s with stops, crossings of the street with turns on the spot at the curbs, quick
//     looks around while walking and standing, full turns on the spot, slow tilts of the sensor,
//     pitch and bob at the step frequency and roll at the stride frequency);
//   - legged: a trotting quadruped at 0.5 m (1-2 m/s, pitch and roll at the trot frequency, turns
//     on the spot up to 90 deg/s);
//   - car events: lane-change swerves and hard braking to standstill;
//   - spin: the sensor turning on the spot at a constant rate.
// Every heading change is a trapezoid of yaw rate (continuous yaw rate, angular acceleration at
// most the style's yaw_accel), so the sensor orientation is smooth at every instant.
#pragma once

#include <string>
#include <vector>

#include "dloam/sim/ego.hpp"
#include "dloam/sim/rng.hpp"

namespace dloam::sim {

enum class Platform { Car, Handheld, Legged };

/// "car" | "handheld" | "legged" (case-insensitive); throws std::invalid_argument otherwise.
Platform parse_platform(const std::string& name);
std::string to_string(Platform platform);

/// How a walking platform moves. Angles in radians, rates in rad/s.
struct WalkStyle {
  double speed_min = 1.0, speed_max = 1.5;  ///< walking speed of each leg (m/s)
  double accel = 0.8;                       ///< starting and stopping (m/s^2)
  double mount_height = 1.5;                ///< sensor above the walked surface (m)
  double yaw_rate_max = M_PI;               ///< peak yaw rate of turns and looks
  double yaw_accel = 400.0 * M_PI / 180.0;  ///< angular acceleration of every heading change
  double look_walking = 0.5;                ///< chance of a quick look aside during a leg
  double look_standing = 0.6;               ///< chance of looking left and right at a stop
  double look_max = 110.0 * M_PI / 180.0;   ///< largest look aside
  double spin_standing = 0.15;              ///< chance of a full turn on the spot at a stop
  double crossing = 0.25;                   ///< chance of crossing the street at the end of a leg
  double step_hz_min = 1.8, step_hz_max = 2.1;
  double gait_pitch = 2.0 * M_PI / 180.0, gait_roll = 2.0 * M_PI / 180.0, gait_bob = 0.03;
  bool roll_at_stride = true;  ///< roll at half the step frequency (a walker sways once per stride)
  double tilt_pitch = 17.0 * M_PI / 180.0, tilt_roll = 14.0 * M_PI / 180.0;  ///< slow tilts (peak)
  double step_length = 0.6;  ///< curbs are stepped up/down over this length (m)
};

/// A person carrying the sensor; `speed` (m/s) is the mean walking speed (legs within +-0.25).
WalkStyle handheld_style(double speed);
/// A trotting quadruped; `speed` (m/s) is the mean speed (legs within +-0.5).
WalkStyle legged_style(double speed);
double default_platform_speed(Platform platform);  ///< handheld 1.25, legged 1.5 (car: 0)

/// Plans a walk from time 0 to `duration` (s): it starts at `start` walking along +x on the line
/// y = start.y() and crosses to y = other_y (and back) now and then. Sets the ego's path (straight
/// legs), speed profile, s0, mount height and body motion. Returns the x of every crossing, so the
/// street can be kept clear there.
std::vector<double> plan_walk(Ego& ego, const WalkStyle& style, Rng& rng, const Vec2& start, double other_y,
                              double duration);

/// Hard braking (8 m/s^2 to standstill, 1.5-4 s standing, 3 m/s^2 back to `v`) and/or lane-change
/// swerves (peak lateral acceleration 6-8 m/s^2, lowered where the yaw rate would pass 30 deg/s)
/// between cruising phases of 2.5-6 s from time 0 to `duration`. `lanes` are the lateral offsets
/// (m, left of the path, 0 included) the car may swerve to. Keeps the ego's path and s0.
void plan_drive_events(Ego& ego, Rng& rng, double v, double duration, bool swerve, bool brake,
                       const std::vector<double>& lanes);

/// The sensor standing at the ego's start, level, turning at `rate` (rad/s, > 0 counter-clockwise)
/// at every instant: yaw(t) = yaw(0) + rate * t.
void plan_spin(Ego& ego, double rate);

/// Appends to `keys` a heading change of `angle` (signed) from t0 as a trapezoid of yaw rate
/// (peak min(rate_max, sqrt(|angle| accel)), ramps at `accel`); returns its duration.
double add_turn(std::vector<RateKey>& keys, double t0, double angle, double rate_max, double accel);

}  // namespace dloam::sim
