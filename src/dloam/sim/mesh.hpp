// Triangle meshes with a SemanticKITTI label and a reflectivity per triangle, and the
// primitives every scene object is built from (box, cylinder, ellipsoid, quad, strip).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/sim/rng.hpp"

namespace dloam::sim {

/// Surface properties of a triangle: its ground-truth label and its reflectivity in [0, 1].
struct Material {
  Label label = semantic::kUnlabeled;
  float reflectivity = 0.5f;
};

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Material> materials;  ///< one per triangle

  [[nodiscard]] std::size_t size() const { return triangles.size(); }
  [[nodiscard]] bool empty() const { return triangles.empty(); }
  std::uint32_t add_vertex(const Vec3& v);
  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, Material m);
  /// Appends `other` transformed by `pose`.
  void append(const Mesh& other, const Pose& pose = Pose::Identity());
  /// Radius of the bounding sphere centred at the origin of the mesh frame.
  [[nodiscard]] double bounding_radius() const;
};

/// Axis-aligned box of full extents `size` centred at `pose` (the box axes follow the pose).
void add_box(Mesh& mesh, const Pose& pose, const Vec3& size, Material m);
/// Box between z0 and z1 over a footprint centred at (x, y) with heading `yaw`.
void add_box_z(Mesh& mesh, double x, double y, double yaw, double length, double width, double z0, double z1,
               Material m);
/// Closed cylinder (or cone when radius_top differs) from `base` to `top`.
void add_cylinder(Mesh& mesh, const Vec3& base, const Vec3& top, double radius, int segments, Material m,
                  double radius_top = -1.0);
/// Ellipsoid from a subdivided icosahedron; `jitter` (fraction of the radius) roughens the
/// surface with random radial offsets (tree crowns).
void add_ellipsoid(Mesh& mesh, const Vec3& center, const Vec3& radii, int subdivisions, Material m,
                   Rng* rng = nullptr, double jitter = 0.0);
/// Quad a-b-c-d (two triangles).
void add_quad(Mesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Material m);

}  // namespace dloam::sim
