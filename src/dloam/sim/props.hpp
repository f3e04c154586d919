// Static scene objects built into the static mesh: terrain-following ground grids, buildings with
// facade detail (pilasters, cornice, so there are edges), walls, fences, guard rails, poles and
// street lamps, trees (trunk + rough crown).
#pragma once

#include <functional>

#include "dloam/sim/ground.hpp"
#include "dloam/sim/mesh.hpp"

namespace dloam::sim {

/// SemanticKITTI classes of static scene parts not named in core/types.hpp.
namespace cls {
inline constexpr Label kRoad = 40;
inline constexpr Label kSidewalk = 48;
inline constexpr Label kBuilding = 50;
inline constexpr Label kFence = 51;
inline constexpr Label kVegetation = 70;
inline constexpr Label kTrunk = 71;
inline constexpr Label kTerrain = 72;
inline constexpr Label kPole = 80;
}  // namespace cls

/// Grid over [x0,x1] x [y0,y1] with cells of about `cell` metres at height terrain + `lift`;
/// `material_at(x, y)` gives the material of each triangle from its centre.
void add_ground_grid(Mesh& mesh, const Ground& ground, double x0, double y0, double x1, double y1,
                     double cell, double lift, const std::function<Material(double, double)>& material_at);
/// Ribbon on the terrain between lateral offsets a and b (left of the path) from s0 to s1.
void add_ground_ribbon(Mesh& mesh, const Ground& ground, const Path& path, double s0, double s1, double a,
                       double b, double step, Material m);
/// Vertical curb face along the segment p0-p1 from the terrain up to terrain + height.
void add_curb(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height, double step,
              Material m);

/// Building whose facade (width along x of the frame) faces direction `yaw + pi/2`, with its
/// facade centre at `front`; extends `depth` behind the facade.
void add_building(Mesh& mesh, Rng& rng, const Ground& ground, const Vec2& front, double yaw, double width,
                  double depth, double height);
/// Wall (label building) or fence panel with posts along p0-p1.
void add_wall(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height,
              double thickness);
void add_fence(Mesh& mesh, const Ground& ground, const Vec2& p0, const Vec2& p1, double height);
/// Guard rail (label fence) along the path at lateral offset `offset` from s0 to s1.
void add_guard_rail(Mesh& mesh, const Ground& ground, const Path& path, double s0, double s1, double offset);
/// Pole (optionally a street lamp with an arm towards `arm_yaw`), label pole.
void add_pole(Mesh& mesh, const Ground& ground, const Vec2& at, double height, bool lamp, double arm_yaw);
/// Tree: trunk (label trunk) and a rough crown (label vegetation).
void add_tree(Mesh& mesh, Rng& rng, const Ground& ground, const Vec2& at, double height);

}  // namespace dloam::sim
