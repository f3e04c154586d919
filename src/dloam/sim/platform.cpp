// Walk plans (handheld, legged), car swerves and braking, turning on the spot.
#include "dloam/sim/platform.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace dloam::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;
}

Platform parse_platform(const std::string& name) {
  std::string n = name;
  for (auto& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (n == "car") return Platform::Car;
  if (n == "handheld") return Platform::Handheld;
  if (n == "legged") return Platform::Legged;
  throw std::invalid_argument("unknown platform '" + name + "' (known: car, handheld, legged)");
}

std::string to_string(Platform platform) {
  switch (platform) {
    case Platform::Car:
      return "car";
    case Platform::Handheld:
      return "handheld";
    case Platform::Legged:
      return "legged";
  }
  return "unknown";
}

WalkStyle handheld_style(double speed) {
  WalkStyle s;
  s.speed_min = std::max(0.5, speed - 0.25);
  s.speed_max = speed + 0.25;
  return s;
}

WalkStyle legged_style(double speed) {
  WalkStyle s;
  s.speed_min = std::max(0.5, speed - 0.5);
  s.speed_max = speed + 0.5;
  s.accel = 1.0;
  s.mount_height = 0.5;
  s.yaw_rate_max = 90.0 * kDeg;
  s.yaw_accel = 180.0 * kDeg;
  s.look_walking = 0.0;
  s.look_standing = 0.0;
  s.spin_standing = 0.15;
  s.step_hz_min = 3.2;
  s.step_hz_max = 3.8;
  s.gait_pitch = 0.8 * kDeg;
  s.gait_roll = 1.0 * kDeg;
  s.gait_bob = 0.01;
  s.roll_at_stride = false;  // a trot rolls with each diagonal pair of legs
  s.tilt_pitch = 3.0 * kDeg;
  s.tilt_roll = 2.0 * kDeg;
  s.step_length = 0.3;
  return s;
}

double default_platform_speed(Platform platform) {
  switch (platform) {
    case Platform::Handheld:
      return 1.25;
    case Platform::Legged:
      return 1.5;
    case Platform::Car:
      return 0.0;
  }
  return 0.0;
}

double add_turn(std::vector<RateKey>& keys, double t0, double angle, double rate_max, double accel) {
  const double a = std::abs(angle), sign = angle < 0.0 ? -1.0 : 1.0;
  if (a <= 0.0) return 0.0;
  const double peak = std::min(rate_max, std::sqrt(a * accel));
  const double ramp = peak / accel, hold = (a - peak * ramp) / peak;
  keys.push_back({t0, 0.0});
  keys.push_back({t0 + ramp, sign * peak});
  keys.push_back({t0 + ramp + hold, sign * peak});
  keys.push_back({t0 + 2.0 * ramp + hold, 0.0});
  return 2.0 * ramp + hold;
}

namespace {
double turn_duration(double angle, double rate_max, double accel) {
  const double a = std::abs(angle), peak = std::min(rate_max, std::sqrt(a * accel));
  return a <= 0.0 ? 0.0 : peak / accel + a / peak;
}

// A look aside and back (out, hold, back), `angle` signed; returns its duration.
double add_look(std::vector<RateKey>& keys, double t0, double angle, double hold, const WalkStyle& s) {
  double t = t0 + add_turn(keys, t0, angle, s.yaw_rate_max, s.yaw_accel) + hold;
  t += add_turn(keys, t, -angle, s.yaw_rate_max, s.yaw_accel);
  return t - t0;
}

double look_duration(double angle, double hold, const WalkStyle& s) {
  return 2.0 * turn_duration(angle, s.yaw_rate_max, s.yaw_accel) + hold;
}
}  // namespace

std::vector<double> plan_walk(Ego& ego, const WalkStyle& s, Rng& rng, const Vec2& start, double other_y,
                              double duration) {
  std::vector<double> crossings;
  std::vector<Vec2> waypoints{start};
  std::vector<SpeedKey> speed;
  std::vector<RateKey> yaw{{0.0, 0.0}};
  Vec2 at = start;
  double t = 0.0, v = uniform(rng, s.speed_min, s.speed_max);  // walking at t = 0
  speed.push_back({0.0, v});
  bool far_side = false;
  const double cross_length = std::abs(other_y - start.y()), cross_dir = other_y > start.y() ? 1.0 : -1.0;
  while (t < duration + 2.0) {
    // A leg along +x from `at` at speed v (already reached), then a stop or a new speed.
    const bool cross = chance(rng, s.crossing);
    const bool stop = cross || chance(rng, 0.6);
    const double v_next = uniform(rng, s.speed_min, s.speed_max);
    const double v_out = stop ? 0.0 : v_next;
    const double ramp_out = std::abs(v - v_out) / s.accel;
    const double cruise = uniform(rng, 6.0, 20.0) / v;  // s
    // A quick look aside while cruising.
    if (chance(rng, s.look_walking)) {
      const double angle = (chance(rng, 0.5) ? 1.0 : -1.0) * uniform(rng, 30.0 * kDeg, 0.7 * s.look_max);
      const double hold = uniform(rng, 0.3, 1.2), need = look_duration(angle, hold, s);
      if (need < cruise - 0.2) add_look(yaw, t + uniform(rng, 0.1, cruise - need - 0.1), angle, hold, s);
    }
    t += cruise;
    speed.push_back({t, v});
    t += ramp_out;
    speed.push_back({t, v_out});
    at.x() += v * cruise + 0.5 * (v + v_out) * ramp_out;
    waypoints.push_back(at);
    if (!stop) {
      v = v_next;
      continue;
    }
    // Standing: look left and right or turn once around, then turn towards the crossing.
    double events = t + 0.2;
    if (chance(rng, s.spin_standing)) {
      events += add_turn(yaw, events, (chance(rng, 0.5) ? 2.0 : -2.0) * M_PI, s.yaw_rate_max, s.yaw_accel);
    } else if (chance(rng, s.look_standing)) {
      const double a = (chance(rng, 0.5) ? 1.0 : -1.0) * uniform(rng, 45.0 * kDeg, s.look_max);
      events += add_turn(yaw, events, a, s.yaw_rate_max, s.yaw_accel) + uniform(rng, 0.3, 1.0);
      events += add_turn(yaw, events, -2.0 * a, s.yaw_rate_max, s.yaw_accel) + uniform(rng, 0.3, 1.0);
      events += add_turn(yaw, events, a, s.yaw_rate_max, s.yaw_accel);
    }
    const double turn = (far_side ? -cross_dir : cross_dir) * 0.5 * M_PI;  // towards the far curb
    if (cross) events += 0.2 + add_turn(yaw, events + 0.2, turn, s.yaw_rate_max, s.yaw_accel);
    t = std::max(t + uniform(rng, 0.5, 3.0), events + 0.1);
    speed.push_back({t, 0.0});
    if (cross) {
      // Across the street (from standstill to standstill), then turn back to +x.
      const double vc = uniform(rng, s.speed_min, s.speed_max), ramp = vc / s.accel;
      const double d_cruise = std::max(0.0, cross_length - vc * ramp);
      t += ramp;
      speed.push_back({t, vc});
      t += d_cruise / vc;
      speed.push_back({t, vc});
      t += ramp;
      speed.push_back({t, 0.0});
      at.y() += (far_side ? -cross_dir : cross_dir) * (vc * ramp + d_cruise);
      waypoints.push_back(at);
      crossings.push_back(at.x());
      far_side = !far_side;
      const double back = t + 0.3 + add_turn(yaw, t + 0.3, -turn, s.yaw_rate_max, s.yaw_accel);
      t = std::max(t + uniform(rng, 0.5, 2.0), back + 0.1);
      speed.push_back({t, 0.0});
    }
    v = v_next;
    t += v / s.accel;
    speed.push_back({t, v});
    at.x() += 0.5 * v * (v / s.accel);
  }
  // The walk goes on straight after its last waypoint; the ramps above land on the waypoints.
  waypoints.push_back(at + Vec2(1.0, 0.0));
  ego.path = Path::from_waypoints(waypoints, 0.0, false);
  ego.s0 = 0.0;
  ego.profile = SpeedProfile(std::move(speed));
  ego.mount_height = s.mount_height;
  BodyMotion& b = ego.body;
  b = BodyMotion{};
  b.enabled = true;
  b.own_heading = true;
  b.yaw0 = 0.0;
  b.yaw = RateProfile(std::move(yaw));
  b.terrain_tilt = false;
  b.step_length = s.step_length;
  b.gait_speed = s.speed_min;
  // Slow tilts: two waves each (periods of 7-14 s and 3-6 s), peaks adding up to the style's.
  auto phase = [&] { return uniform(rng, 0.0, 2.0 * M_PI); };
  b.pitch = {{0.6 * s.tilt_pitch, uniform(rng, 0.07, 0.14), phase()},
             {0.4 * s.tilt_pitch, uniform(rng, 0.17, 0.33), phase()}};
  b.roll = {{0.6 * s.tilt_roll, uniform(rng, 0.07, 0.14), phase()},
            {0.4 * s.tilt_roll, uniform(rng, 0.17, 0.33), phase()}};
  const double step_hz = uniform(rng, s.step_hz_min, s.step_hz_max), step_phase = phase();
  b.gait_pitch = {{s.gait_pitch, step_hz, step_phase}};
  b.gait_bob = {{s.gait_bob, step_hz, step_phase + 0.5 * M_PI}};
  b.gait_roll = {{s.gait_roll, s.roll_at_stride ? 0.5 * step_hz : step_hz, phase()}};
  return crossings;
}

void plan_drive_events(Ego& ego, Rng& rng, double v, double duration, bool swerve, bool brake,
                       const std::vector<double>& lanes) {
  constexpr double kBrake = 8.0, kAccel = 3.0, kMaxYawRate = 30.0 * kDeg;
  std::vector<SpeedKey> keys{{0.0, v}};
  std::vector<LaneShift> shifts;
  double t = 0.0, lane = 0.0;
  while (t < duration && (swerve || brake)) {
    t += uniform(rng, 2.5, 6.0);
    const bool do_swerve = swerve && (!brake || chance(rng, 0.5));
    if (do_swerve) {
      std::vector<double> targets;
      for (double l : lanes)
        if (std::abs(l - lane) > 0.5) targets.push_back(l);
      if (targets.empty()) continue;
      const double target =
          targets[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(targets.size()) - 1))];
      const double shift = target - lane;
      // The heading follows the velocity, so the yaw rate peaks near a_lat / v.
      const double a_lat = std::min(uniform(rng, 6.0, 8.0), v * kMaxYawRate);
      const double T = std::sqrt(2.0 * M_PI * std::abs(shift) / a_lat);
      shifts.push_back({t, T, shift});
      t += T;
      lane = target;
      if (chance(rng, 0.4)) {  // evasive: straight back to where it was
        t += uniform(rng, 0.3, 1.0);
        shifts.push_back({t, T, -shift});
        t += T;
        lane -= shift;
      }
    } else {
      keys.push_back({t, v});
      t += v / kBrake;
      keys.push_back({t, 0.0});
      t += uniform(rng, 1.5, 4.0);
      keys.push_back({t, 0.0});
      t += v / kAccel;
      keys.push_back({t, v});
    }
  }
  ego.profile = SpeedProfile(std::move(keys));
  ego.body = BodyMotion{};
  ego.body.enabled = !shifts.empty();
  ego.body.shifts = std::move(shifts);
}

void plan_spin(Ego& ego, double rate) {
  ego.body = BodyMotion{};
  ego.body.enabled = true;
  ego.body.own_heading = true;
  ego.body.yaw0 = ego.path.at(ego.s0).yaw;
  ego.body.yaw = RateProfile::constant(rate);
  ego.body.terrain_tilt = false;
  ego.profile = SpeedProfile::constant(0.0);
}

}  // namespace dloam::sim
