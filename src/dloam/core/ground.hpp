// Ground extraction on the range image (paper III.C, eq. 7): two vertically adjacent pixels
// among the lowest beams are ground when the line joining their points is nearly horizontal.
// Also fits the ground plane (least squares / PCA) whose normal the pre-registration needs.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// III.C ground extraction (eq. 7).
struct GroundConfig {
  double ground_pitch_deg = 10.0;  ///< eq. 7 threshold
  int N_ground_rows = 0;           ///< rows (from the bottom) searched for ground; 0 = beams below -1 deg
};

struct GroundResult {
  std::vector<std::uint8_t> mask;  ///< rows*cols, 1 = ground pixel
  int num_ground = 0;              ///< number of ground pixels
  /// Unit normal of the least-squares ground plane, pointing up (z > 0); +z when fewer than
  /// three ground pixels were found (then `plane_valid` is false).
  Vec3 normal = Vec3::UnitZ();
  /// Plane: normal.dot(p) + height = 0, so `height` is how far the sensor origin is above it.
  double height = 0.0;
  bool plane_valid = false;
};

/// Number of rows (from the bottom) searched for ground. `N_ground_rows > 0` is used as is
/// (clamped to the image); 0 = auto: every beam pointing at least 1 deg below the horizon
/// (a sensor about 2 m high sees flat ground below -1 deg within ~115 m, i.e. within range),
/// so beams near and above the horizon, which only hit objects, are never ground candidates.
int ground_search_rows(const SensorConfig& sensor, const GroundConfig& config);

/// Eq. 7 per column over adjacent rows v, v+1 < ground_search_rows() (v, v+2 when the pixel in
/// row v+1 is empty: range-image holes would otherwise leave ground unlabelled): both pixels valid,
/// |atan2(dz, hypot(dx, dy))| < ground_pitch_deg, and the upper point at least half the
/// beam gap (r * delta elevation) farther out horizontally -> both are ground. A plane is then
/// fitted (least squares, two refits on its 0.15 m inliers) to the ground pixels within
/// `plane_radius` metres (horizontal) of the sensor, or to all of them when fewer than 50 lie
/// that close, and ground pixels within `plane_radius` more than `max_height` above it are
/// dropped (flat object tops).
GroundResult extract_ground(const std::vector<Vec3>& points, const RangeImage& image,
                            const SensorConfig& sensor, const GroundConfig& config,
                            double plane_radius = 25.0, double max_height = 0.4);

}  // namespace dloam
