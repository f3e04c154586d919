// Terrain height/slope and poses of objects standing on it.
#include "dloam/sim/ground.hpp"

#include <algorithm>
#include <cmath>

namespace dloam::sim {

namespace {
constexpr double kYStretch = 0.8;  // different wavelength along y so the terrain is not symmetric
}

double Ground::terrain(double x, double y) const {
  if (amplitude == 0.0) return 0.0;
  const double k = 2.0 * M_PI / wavelength;
  return 0.5 * amplitude * (std::sin(k * x + phase_x) + std::sin(kYStretch * k * y + phase_y));
}

Vec2 Ground::gradient(double x, double y) const {
  if (amplitude == 0.0) return Vec2::Zero();
  const double k = 2.0 * M_PI / wavelength;
  return 0.5 * amplitude *
         Vec2(k * std::cos(k * x + phase_x), kYStretch * k * std::cos(kYStretch * k * y + phase_y));
}

double Ground::surface(double x, double y) const {
  double h = terrain(x, y);
  for (const auto& r : raised)
    if (r.contains(x, y)) return h + r.height;
  return h;
}

double Ground::stepped_surface(double x, double y, double step_length) const {
  double lift = 0.0;
  for (const auto& r : raised) {
    // Signed distance to the rectangle's edge: positive inside.
    const double qx = std::max({r.x0 - x, 0.0, x - r.x1}), qy = std::max({r.y0 - y, 0.0, y - r.y1});
    const double sd =
        (qx > 0.0 || qy > 0.0) ? -std::hypot(qx, qy) : std::min({x - r.x0, r.x1 - x, y - r.y0, r.y1 - y});
    const double u = std::clamp(sd / step_length + 0.5, 0.0, 1.0);
    lift = std::max(lift, r.height * u * u * (3.0 - 2.0 * u));
  }
  return terrain(x, y) + lift;
}

Pose ground_pose(const Ground& ground, const PathPoint& pp, double height_above_surface, bool tilt) {
  const double x = pp.p.x(), y = pp.p.y();
  Pose pose = Pose::Identity();
  pose.translate(Vec3(x, y, ground.surface(x, y) + height_above_surface));
  pose.rotate(Eigen::AngleAxisd(pp.yaw, Vec3::UnitZ()));
  if (tilt) {
    const Vec2 g = ground.gradient(x, y);
    const Vec2 fwd(std::cos(pp.yaw), std::sin(pp.yaw)), left(-std::sin(pp.yaw), std::cos(pp.yaw));
    pose.rotate(Eigen::AngleAxisd(-std::atan(g.dot(fwd)), Vec3::UnitY()));  // nose up when climbing
    pose.rotate(Eigen::AngleAxisd(std::atan(g.dot(left)), Vec3::UnitX()));  // left side up
  }
  return pose;
}

}  // namespace dloam::sim
