// Ground of a scene: a gentle smooth terrain (sum of two long sine waves, grades of a few percent)
// plus raised areas (city blocks: sidewalk slabs on top of the terrain, with curbs). Vehicles and
// people stand on it; ground_pose() places a path point on it.
#pragma once

#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/sim/path.hpp"

namespace dloam::sim {

/// Axis-aligned rectangle raised `height` above the terrain (a block with sidewalk slab).
struct RaisedArea {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  double height = 0.15;
  [[nodiscard]] bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

struct Ground {
  double amplitude = 0.0;     ///< peak height of the terrain undulation (m)
  double wavelength = 400.0;  ///< of the undulation (m); max grade = pi * amplitude / wavelength
  double phase_x = 0.0, phase_y = 0.0;
  std::vector<RaisedArea> raised;

  /// Terrain height (road level) at (x, y).
  [[nodiscard]] double terrain(double x, double y) const;
  /// d(terrain)/dx, d(terrain)/dy.
  [[nodiscard]] Vec2 gradient(double x, double y) const;
  /// Height of the walkable surface: terrain plus the raised area containing (x, y), if any.
  [[nodiscard]] double surface(double x, double y) const;
  /// surface() with each raised area's edge (curb) spread over `step_length` metres centred on it
  /// (smoothstep across the edge): where a walker's feet carry the body up or down a curb.
  [[nodiscard]] double stepped_surface(double x, double y, double step_length) const;
};

/// Pose of an object standing on the ground at `pp` (x forward along the path, z up). With `tilt`,
/// pitch and roll follow the terrain slope (vehicles); without, the object stays upright (people).
Pose ground_pose(const Ground& ground, const PathPoint& pp, double height_above_surface, bool tilt);

}  // namespace dloam::sim
