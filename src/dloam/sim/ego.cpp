// Sensor pose of the ego platform at any instant: path motion, swerves, own heading, body motion.
#include "dloam/sim/ego.hpp"

#include <algorithm>
#include <cmath>

namespace dloam::sim {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;

double sum_of(const std::vector<Wave>& waves, double t) {
  double v = 0.0;
  for (const Wave& w : waves) v += w.at(t);
  return v;
}
}  // namespace

double LaneShift::offset(double t) const {
  const double u = (t - t0) / duration;
  if (u <= 0.0) return 0.0;
  if (u >= 1.0) return shift;
  return shift * (u - std::sin(kTwoPi * u) / kTwoPi);
}

double LaneShift::rate(double t) const {
  const double u = (t - t0) / duration;
  if (u <= 0.0 || u >= 1.0) return 0.0;
  return shift / duration * (1.0 - std::cos(kTwoPi * u));
}

double LaneShift::accel(double t) const {
  const double u = (t - t0) / duration;
  if (u <= 0.0 || u >= 1.0) return 0.0;
  return shift / (duration * duration) * kTwoPi * std::sin(kTwoPi * u);
}

double Wave::at(double t) const { return amplitude * std::sin(kTwoPi * frequency_hz * t + phase); }

double Ego::lateral_offset(double t) const {
  double d = 0.0;
  for (const LaneShift& s : body.shifts) d += s.offset(t);
  return d;
}

double Ego::lateral_rate(double t) const {
  double d = 0.0;
  for (const LaneShift& s : body.shifts) d += s.rate(t);
  return d;
}

double Ego::gait(double t) const {
  const double x = std::clamp(profile.speed(t) / body.gait_speed, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

Vec2 Ego::position(double t) const {
  const PathPoint pp = path.at(s0 + profile.distance(t));
  if (!body.enabled || body.shifts.empty()) return pp.p;
  return pp.p + lateral_offset(t) * Vec2(-std::sin(pp.yaw), std::cos(pp.yaw));
}

Pose Ego::sensor_pose(const Ground& ground, double t) const {
  const PathPoint pp = path.at(s0 + profile.distance(t));
  if (!body.enabled) return ground_pose(ground, pp, mount_height, true);

  PathPoint at = pp;
  if (!body.shifts.empty()) {
    at.p += lateral_offset(t) * Vec2(-std::sin(pp.yaw), std::cos(pp.yaw));
    // A car points where it goes: its velocity is the path speed plus the lateral rate.
    const double lateral = lateral_rate(t);
    if (lateral != 0.0) at.yaw += std::atan2(lateral, profile.speed(t));
  }
  at.yaw = body.own_heading ? body.yaw0 + body.yaw.value(t) : at.yaw + body.yaw.value(t);

  const double e = gait(t);
  const double surface = body.step_length > 0.0 ? ground.stepped_surface(at.p.x(), at.p.y(), body.step_length)
                                                : ground.surface(at.p.x(), at.p.y());
  const double z = surface + mount_height + e * sum_of(body.gait_bob, t);
  Pose pose = Pose::Identity();
  pose.translate(Vec3(at.p.x(), at.p.y(), z));
  pose.rotate(Eigen::AngleAxisd(at.yaw, Vec3::UnitZ()));
  if (body.terrain_tilt) {
    const Vec2 g = ground.gradient(at.p.x(), at.p.y());
    const Vec2 fwd(std::cos(at.yaw), std::sin(at.yaw)), left(-std::sin(at.yaw), std::cos(at.yaw));
    pose.rotate(Eigen::AngleAxisd(-std::atan(g.dot(fwd)), Vec3::UnitY()));
    pose.rotate(Eigen::AngleAxisd(std::atan(g.dot(left)), Vec3::UnitX()));
  }
  const double pitch = sum_of(body.pitch, t) + e * sum_of(body.gait_pitch, t);
  const double roll = sum_of(body.roll, t) + e * sum_of(body.gait_roll, t);
  pose.rotate(Eigen::AngleAxisd(pitch, Vec3::UnitY()));
  pose.rotate(Eigen::AngleAxisd(roll, Vec3::UnitX()));
  return pose;
}

}  // namespace dloam::sim
