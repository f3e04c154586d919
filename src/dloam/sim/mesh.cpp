// Mesh primitives. Triangles are double-sided for Embree, so winding order does not matter.
#include "dloam/sim/mesh.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace dloam::sim {

std::uint32_t Mesh::add_vertex(const Vec3& v) {
  vertices.push_back(v.cast<float>());
  return static_cast<std::uint32_t>(vertices.size() - 1);
}

void Mesh::add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, Material m) {
  triangles.push_back({a, b, c});
  materials.push_back(m);
}

void Mesh::append(const Mesh& other, const Pose& pose) {
  const auto offset = static_cast<std::uint32_t>(vertices.size());
  for (const auto& v : other.vertices) vertices.push_back((pose * v.cast<double>()).cast<float>());
  for (const auto& t : other.triangles) triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  materials.insert(materials.end(), other.materials.begin(), other.materials.end());
}

double Mesh::bounding_radius() const {
  double r = 0.0;
  for (const auto& v : vertices) r = std::max(r, static_cast<double>(v.norm()));
  return r;
}

void add_quad(Mesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Material m) {
  const auto ia = mesh.add_vertex(a), ib = mesh.add_vertex(b), ic = mesh.add_vertex(c),
             id = mesh.add_vertex(d);
  mesh.add_triangle(ia, ib, ic, m);
  mesh.add_triangle(ia, ic, id, m);
}

void add_box(Mesh& mesh, const Pose& pose, const Vec3& size, Material m) {
  const Vec3 h = 0.5 * size;
  std::array<std::uint32_t, 8> v{};
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
    v[static_cast<std::size_t>(i)] = mesh.add_vertex(pose * corner);
  }
  // Six faces as quads of corner indices (bit 0 = x, bit 1 = y, bit 2 = z).
  static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : kFaces) {
    mesh.add_triangle(v[f[0]], v[f[1]], v[f[2]], m);
    mesh.add_triangle(v[f[0]], v[f[2]], v[f[3]], m);
  }
}

void add_box_z(Mesh& mesh, double x, double y, double yaw, double length, double width, double z0, double z1,
               Material m) {
  Pose pose = Pose::Identity();
  pose.translate(Vec3(x, y, 0.5 * (z0 + z1)));
  pose.rotate(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
  add_box(mesh, pose, Vec3(length, width, z1 - z0), m);
}

void add_cylinder(Mesh& mesh, const Vec3& base, const Vec3& top, double radius, int segments, Material m,
                  double radius_top) {
  if (radius_top < 0.0) radius_top = radius;
  const Vec3 axis = (top - base).normalized();
  const Vec3 u = axis.unitOrthogonal();
  const Vec3 w = axis.cross(u);
  const auto n = static_cast<std::uint32_t>(segments);
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    const Vec3 radial = std::cos(a) * u + std::sin(a) * w;
    mesh.add_vertex(base + radius * radial);
    mesh.add_vertex(top + radius_top * radial);
  }
  const auto cb = mesh.add_vertex(base), ct = mesh.add_vertex(top);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    const std::uint32_t b0 = first + 2 * i, t0 = b0 + 1, b1 = first + 2 * j, t1 = b1 + 1;
    mesh.add_triangle(b0, b1, t1, m);
    mesh.add_triangle(b0, t1, t0, m);
    mesh.add_triangle(cb, b1, b0, m);
    mesh.add_triangle(ct, t0, t1, m);
  }
}

namespace {
// Unit icosphere: vertices on the unit sphere and faces, subdivided `levels` times.
void icosphere(int levels, std::vector<Vec3>& verts, std::vector<std::array<std::uint32_t, 3>>& faces) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  verts = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : verts) v.normalize();
  faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
           {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
           {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
    auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      verts.push_back((verts[a] + verts[b]).normalized());
      const auto idx = static_cast<std::uint32_t>(verts.size() - 1);
      midpoint.emplace(key, idx);
      return idx;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& f : faces) {
      const auto a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    faces = std::move(next);
  }
}
}  // namespace

void add_ellipsoid(Mesh& mesh, const Vec3& center, const Vec3& radii, int subdivisions, Material m, Rng* rng,
                   double jitter) {
  std::vector<Vec3> verts;
  std::vector<std::array<std::uint32_t, 3>> faces;
  icosphere(subdivisions, verts, faces);
  const auto offset = static_cast<std::uint32_t>(mesh.vertices.size());
  for (const auto& v : verts) {
    const double scale = (rng != nullptr && jitter > 0.0) ? 1.0 + uniform(*rng, -jitter, jitter) : 1.0;
    mesh.add_vertex(center + scale * v.cwiseProduct(radii));
  }
  for (const auto& f : faces) mesh.add_triangle(f[0] + offset, f[1] + offset, f[2] + offset, m);
}

}  // namespace dloam::sim
