// Refinement of T_coarse by a projective point-to-plane alignment of two range images. This is
// dloam's addition to the pre-registration (III.D.1), not in the paper.
//
// Why: the PCA objects of a sparse sensor (16-32 beams) leave the coarse motion 0.5-1 deg and
// 0.1 m off. Eq. 13's v_static is 0.1 m per scan, so such an error makes the facades along a street
// "move" (measured on simulated VLP-16 drives: docs/results.md, 16 beams).
//
// How: each sampled current point is moved into the previous frame with the current estimate
// (P^{k->k-1}) and paired with the previous scan's point in the pixel it lands in. This is eqs.
// 4-5's projection, so there is no search. The residual is that point's distance to the previous
// surface, along the surface normal taken from the point's image neighbours. Gauss-Newton runs on
// these residuals with Tukey weights that narrow from `initial_width` to `final_width`, so
// moving objects (residuals of their motion per scan) stop counting.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// The previous scan's range image as points: per pixel the nearest point (own frame) and its
/// range; empty pixels hold the zero point and range 0.
struct VertexMap {
  int rows = 0, cols = 0;
  std::vector<Eigen::Vector3f> point;
  std::vector<float> range;
  /// fill_vertex_map's work buffer (nearest point per pixel), kept with the map so that refilling
  /// it reuses the memory: fresh pages every scan cost 0.4 ms on a 64 x 2048 image.
  std::vector<std::uint64_t> nearest_key;
  [[nodiscard]] bool empty() const { return point.empty(); }
};

/// The image of `points` whose pixels are `pixel_of_point` (-1: none): per pixel the nearest point.
/// Fills `map` in place, keeping its memory (buffers included).
void fill_vertex_map(const std::vector<Vec3>& points, const std::vector<int>& pixel_of_point, int rows,
                     int cols, VertexMap& map);
VertexMap make_vertex_map(const std::vector<Vec3>& points, const std::vector<int>& pixel_of_point, int rows,
                          int cols);

/// Unit normal of the surface at pixel (row, col), facing the sensor, from the left/right and
/// lower/upper neighbour pixels (one-sided when a neighbour is missing or lies on another surface,
/// farther than a fraction of the range); zero when there is none.
Eigen::Vector3f surface_normal(const VertexMap& map, int row, int col);

struct AlignmentOptions {
  int iterations = 8;
  int max_points = 2000;          ///< current points used (every n-th pixel)
  double initial_width = 1.0;     ///< m: Tukey width of the first iteration
  double final_width = 0.2;       ///< m: ... of the last (halving per iteration until then)
  double min_inlier_ratio = 0.3;  ///< fewer weighted pairs than this fraction of the samples: no result
};

struct AlignmentResult {
  Pose T = Pose::Identity();  ///< current -> previous frame
  bool valid = false;
  int pairs = 0;  ///< samples with a non-zero weight in the last iteration
};

/// Aligns the current scan onto `previous`, starting from `initial`: `points` in the current
/// frame and its range image's `point_of_pixel` (the samples are taken per pixel).
AlignmentResult align_range_images(const std::vector<Vec3>& points, const std::vector<int>& point_of_pixel,
                                   const VertexMap& previous, const SensorConfig& sensor, const Pose& initial,
                                   const AlignmentOptions& options = {});

}  // namespace dloam
