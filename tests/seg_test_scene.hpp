// Analytic scene for the segmentation / feature tests: a spinning 32-beam sensor 1.73 m above a
// flat ground, with a pole, a building block (convex vertical corner facing the sensor), a wall
// behind the sensor straddling column 0, a small sign (too small to be a cluster) and a thin
// floating post (small but tall: kept). One ray per pixel centre, so each pixel holds exactly
// the point of the primitive its ray hits first; `hit[i]` says which.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam::test {

enum Hit { kGround = 0, kPole, kBuilding, kRearWall, kSign, kPost };

struct Box {
  Vec3 lo, hi;
};
struct Cylinder {
  double cx, cy, radius, z_lo, z_hi;
};

struct Scene {
  SensorConfig sensor;
  double height = 1.73;  ///< sensor above ground (ground plane z = -height)
  Cylinder pole{8.0, 4.0, 0.15, -1.73, 1.27};
  Box building{{10.0, -12.0, -1.73}, {16.0, -6.0, 2.27}};
  Box rear_wall{{-9.0, -2.0, -1.73}, {-8.7, 2.0, 0.77}};
  Box sign;  ///< one beam row high, set in make_scene()
  Box post{{25.0, 10.0, -1.23}, {25.4, 10.4, 0.27}};
  std::vector<Vec3> points;
  std::vector<int> hit;
  std::vector<int> row, col;  ///< pixel the ray was cast through
};

inline SensorConfig scene_sensor() {
  SensorConfig s;
  s.preset = "test-32";
  s.N_scan = 32;
  s.Horizon_SCAN = 1024;
  s.Pit_bottom = -24.9;
  s.fov_top = 2.0;
  s.min_range = 1.0;
  s.max_range = 80.0;
  return s;
}

namespace detail {
constexpr double kInf = std::numeric_limits<double>::infinity();

inline double ray_box(const Vec3& d, const Box& b) {
  double t0 = 0.0, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (0.0 < b.lo[k] || 0.0 > b.hi[k]) return kInf;
      continue;
    }
    double a = b.lo[k] / d[k], c = b.hi[k] / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return t0 <= t1 && t0 > 0.0 ? t0 : kInf;
}

inline double ray_cylinder(const Vec3& d, const Cylinder& c) {
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = -2.0 * (d.x() * c.cx + d.y() * c.cy);
  const double q = c.cx * c.cx + c.cy * c.cy - c.radius * c.radius;
  const double disc = b * b - 4.0 * a * q;
  if (a < 1e-12 || disc < 0.0) return kInf;
  const double t = (-b - std::sqrt(disc)) / (2.0 * a);
  const double z = t * d.z();
  return t > 0.0 && z >= c.z_lo && z <= c.z_hi ? t : kInf;
}
}  // namespace detail

/// The nearest hit along a ray so far: distance and what was hit.
struct Nearest {
  double t = detail::kInf;
  int id = -1;
  void consider(double t_hit, int which) {
    if (t_hit < t) t = t_hit, id = which;
  }
};

/// Calls f(row, col, d) with the unit ray d through the centre of every pixel of the sensor's
/// range image (column centres in sweep order, range_image.hpp).
template <class F>
void for_each_pixel_ray(const SensorConfig& sensor, F&& f) {
  for (int v = 0; v < sensor.N_scan; ++v) {
    const double e = sensor.beam_elevation_deg(v) * M_PI / 180.0;
    for (int u = 0; u < sensor.Horizon_SCAN; ++u) {
      const double a = M_PI - 2.0 * M_PI * (u + 0.5) / sensor.Horizon_SCAN;
      f(v, u, Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)));
    }
  }
}

/// Distance along the unit ray d to flat ground `height` below the sensor (inf looking up).
inline double ground_distance(const Vec3& d, double height) {
  return d.z() < 0.0 ? -height / d.z() : detail::kInf;
}

/// Casts one ray through every pixel centre of the sensor's range image.
inline Scene make_scene() {
  Scene s;
  s.sensor = scene_sensor();
  // A 1 m wide, 0.16 m tall sign 15 m ahead-left, centred on beam row 25: 1 row, ~11 pixels.
  const double e25 = s.sensor.beam_elevation_deg(25) * M_PI / 180.0;
  const double zc = 15.0 * std::tan(e25);
  s.sign = Box{{15.0, 4.0, zc - 0.08}, {15.05, 5.0, zc + 0.08}};
  for_each_pixel_ray(s.sensor, [&](int v, int u, const Vec3& d) {
    Nearest n{ground_distance(d, s.height), kGround};
    n.consider(detail::ray_cylinder(d, s.pole), kPole);
    n.consider(detail::ray_box(d, s.building), kBuilding);
    n.consider(detail::ray_box(d, s.rear_wall), kRearWall);
    n.consider(detail::ray_box(d, s.sign), kSign);
    n.consider(detail::ray_box(d, s.post), kPost);
    if (n.t > s.sensor.max_range) return;
    s.points.push_back(n.t * d);
    s.hit.push_back(n.id);
    s.row.push_back(v);
    s.col.push_back(u);
  });
  return s;
}

/// Height of a point above the ground plane.
inline double height_above_ground(const Scene& s, const Vec3& p) { return p.z() + s.height; }

}  // namespace dloam::test
