// Static props. Everything stands on the terrain: bases are sunk below the lowest ground point of
// their footprint so no gaps appear on slopes.
#include "dloam/sim/props.hpp"

#include <algorithm>
#include <cmath>

namespace dloam::sim {

namespace {
Pose frame_at(double x, double y, double z, double yaw) {
  Pose p = Pose::Identity();
  p.translate(Vec3(x, y, z));
  p.rotate(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
  return p;
}
// Box given by its ranges in a local frame.
void add_box_range(Mesh& mesh, const Pose& frame, double x0, double x1, double y0, double y1, double z0,
                   double z1, Material m) {
  Pose p = frame;
  p.translate(Vec3(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)));
  add_box(mesh, p, Vec3(x1 - x0, y1 - y0, z1 - z0), m);
}
Vec2 left_of(double yaw) { return {-std::sin(yaw), std::cos(yaw)}; }
}  // namespace

void add_ground_grid(Mesh& mesh, const Ground& ground, double x0, double y0, double x1, double y1,
                     double cell, double lift, const std::function<Material(double, double)>& material_at) {
  const int nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell)));
  const int ny = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell)));
  const double dx = (x1 - x0) / nx, dy = (y1 - y0) / ny;
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + i * dx, y = y0 + j * dy;
      mesh.add_vertex(Vec3(x, y, ground.terrain(x, y) + lift));
    }
  auto idx = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Material m = material_at(x0 + (i + 0.5) * dx, y0 + (j + 0.5) * dy);
      mesh.add_triangle(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), m);
      mesh.add_triangle(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1), m);
    }
}

void add_ground_ribbon(Mesh& mesh, const Ground& ground, const Path& path, double s0, double s1, double a,
                       double b, double step, Material m) {
  const int n = std::max(1, static_cast<int>(std::ceil((s1 - s0) / step)));
  std::uint32_t prev_a = 0, prev_b = 0;
  for (int i = 0; i <= n; ++i) {
    const PathPoint pp = path.at(s0 + (s1 - s0) * i / n);
    const Vec2 pa = pp.p + a * left_of(pp.yaw), pb = pp.p + b * left_of(pp.yaw);
    const auto ia = mesh.add_vertex(Vec3(pa.x(), pa.y(), ground.terrain(pa.x(), pa.y())));
    const auto ib = mesh.add_vertex(Vec3(pb.x(), pb.y(), ground.terrain(pb.x(), pb.y())));
    if (i > 0) {
      mesh.add_triangle(prev_a, prev_b, ib, m);
      mesh.add_triangle(prev_a, ib, ia, m);
    }
    prev_a = ia;
    prev_b = ib;
  }
}

void add_curb(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height, double step,
              Material m) {
  const int n = std::max(1, static_cast<int>(std::ceil((p1 - p0).norm() / step)));
  for (int i = 0; i < n; ++i) {
    const Vec2 a = p0 + (p1 - p0) * i / n, b = p0 + (p1 - p0) * (i + 1) / n;
    const double za = ground.terrain(a.x(), a.y()), zb = ground.terrain(b.x(), b.y());
    add_quad(mesh, Vec3(a.x(), a.y(), za - 0.05), Vec3(b.x(), b.y(), zb - 0.05),
             Vec3(b.x(), b.y(), zb + height), Vec3(a.x(), a.y(), za + height), m);
  }
}

void add_building(Mesh& mesh, Rng& rng, const Ground& ground, const Vec2& front, double yaw, double width,
                  double depth, double height) {
  const Pose flat = frame_at(front.x(), front.y(), 0.0, yaw);
  double base = ground.terrain(front.x(), front.y());
  for (double cx : {-0.5, 0.5})
    for (double cy : {0.0, -1.0}) {
      const Vec3 c = flat * Vec3(cx * width, cy * depth, 0.0);
      base = std::min(base, ground.terrain(c.x(), c.y()));
    }
  const double top = ground.terrain(front.x(), front.y()) + height;
  const Pose f = frame_at(front.x(), front.y(), 0.0, yaw);
  const Material wall{cls::kBuilding, static_cast<float>(uniform(rng, 0.25, 0.7))};
  const Material trim{cls::kBuilding, static_cast<float>(uniform(rng, 0.3, 0.8))};
  const double hw = 0.5 * width;
  add_box_range(mesh, f, -hw, hw, -depth, 0.0, base - 0.5, top, wall);
  // Pilasters on the facade: vertical edges every few metres.
  const double spacing = uniform(rng, 3.0, 6.0);
  for (double x = -hw + 0.2; x <= hw - 0.2; x += spacing)
    add_box_range(mesh, f, x - 0.2, x + 0.2, 0.0, 0.25, base - 0.5, top, trim);
  // Cornice and optional floor ledges: horizontal edges.
  add_box_range(mesh, f, -hw - 0.2, hw + 0.2, -depth - 0.2, 0.45, top, top + 0.4, trim);
  if (chance(rng, 0.5))
    for (double z = base + 3.5; z < top - 1.5; z += 3.2)
      add_box_range(mesh, f, -hw, hw, 0.0, 0.3, z, z + 0.2, trim);
}

void add_wall(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height,
              double thickness) {
  const Vec2 mid = 0.5 * (p0 + p1), d = p1 - p0;
  const double z0 = std::min({ground.terrain(p0.x(), p0.y()), ground.terrain(p1.x(), p1.y()),
                              ground.terrain(mid.x(), mid.y())}) -
                    0.3;
  const double z1 = ground.terrain(mid.x(), mid.y()) + height;
  add_box_z(mesh, mid.x(), mid.y(), std::atan2(d.y(), d.x()), d.norm(), thickness, z0, z1,
            {cls::kBuilding, 0.45f});
}

void add_fence(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height) {
  constexpr double kPiece = 2.5;
  const Material m{cls::kFence, 0.55f};
  const Vec2 d = p1 - p0;
  const double yaw = std::atan2(d.y(), d.x());
  const int n = std::max(1, static_cast<int>(std::ceil(d.norm() / kPiece)));
  for (int i = 0; i < n; ++i) {
    const Vec2 a = p0 + d * i / n, b = p0 + d * (i + 1) / n, mid = 0.5 * (a + b);
    const double z = ground.terrain(mid.x(), mid.y());
    add_box_z(mesh, mid.x(), mid.y(), yaw, (b - a).norm(), 0.03, z + 0.1, z + height, m);  // panel
    add_box_z(mesh, a.x(), a.y(), yaw, 0.08, 0.08, z - 0.2, z + height + 0.05, m);         // post
  }
}

void add_guard_rail(Mesh& mesh, const Ground& ground, const Path& path, double s0, double s1, double offset) {
  constexpr double kStep = 4.0;
  const Material m{cls::kFence, 0.6f};
  const int n = std::max(1, static_cast<int>(std::ceil((s1 - s0) / kStep)));
  for (int i = 0; i < n; ++i) {
    const PathPoint a = path.at(s0 + (s1 - s0) * i / n), b = path.at(s0 + (s1 - s0) * (i + 1) / n);
    const Vec2 pa = a.p + offset * left_of(a.yaw), pb = b.p + offset * left_of(b.yaw);
    const double za = ground.terrain(pa.x(), pa.y()), zb = ground.terrain(pb.x(), pb.y());
    add_quad(mesh, Vec3(pa.x(), pa.y(), za + 0.45), Vec3(pb.x(), pb.y(), zb + 0.45),
             Vec3(pb.x(), pb.y(), zb + 0.78), Vec3(pa.x(), pa.y(), za + 0.78), m);
    add_box_z(mesh, pa.x(), pa.y(), a.yaw, 0.12, 0.12, za - 0.1, za + 0.7, m);
  }
}

void add_pole(Mesh& mesh, const Ground& ground, const Vec2& at, double height, bool lamp, double arm_yaw) {
  const Material m{cls::kPole, 0.6f};
  const double z = ground.terrain(at.x(), at.y());
  const Vec3 top(at.x(), at.y(), z + height);
  add_cylinder(mesh, Vec3(at.x(), at.y(), z - 0.3), top, 0.09, 8, m, 0.07);
  if (!lamp) return;
  const Vec3 arm_end = top + Vec3(1.6 * std::cos(arm_yaw), 1.6 * std::sin(arm_yaw), 0.2);
  add_cylinder(mesh, top - Vec3(0, 0, 0.1), arm_end, 0.05, 6, m);
  add_box_z(mesh, arm_end.x(), arm_end.y(), arm_yaw, 0.6, 0.25, arm_end.z() - 0.2, arm_end.z(), m);
}

void add_tree(Mesh& mesh, Rng& rng, const Ground& ground, const Vec2& at, double height) {
  const double z = ground.terrain(at.x(), at.y());
  const double crown_base = z + height * uniform(rng, 0.3, 0.45);
  add_cylinder(mesh, Vec3(at.x(), at.y(), z - 0.3), Vec3(at.x(), at.y(), crown_base + 0.8),
               uniform(rng, 0.12, 0.28), 8, {cls::kTrunk, 0.35f});
  const double r = uniform(rng, 1.4, 3.0);
  const double rz = 0.5 * (z + height - crown_base);
  add_ellipsoid(mesh, Vec3(at.x(), at.y(), crown_base + rz), Vec3(r, r * uniform(rng, 0.85, 1.15), rz), 1,
                {cls::kVegetation, 0.3f}, &rng, 0.22);
}

}  // namespace dloam::sim
