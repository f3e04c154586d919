// Speed matrix (paper eq. 13): the current scan, de-skewed and moved into the previous scan's
// frame (P^{k->k-1}), is projected with eqs. 4-5 onto the previous scan's range image P^{k-1}_{U,V};
// each pixel's speed is the range difference s = |r^k - r^{k-1}| (metres per scan). The two
// projections do not fall on the same pixel centres: on surfaces seen at a grazing angle (the
// ground, walls along the street) one pixel of offset changes the range by decimetres. So r^{k-1}
// is the interval spanned by the 2x2 previous pixels bracketing the point's direction, and s is
// the distance of r^k to that interval (0 inside it): a smooth static surface gives ~0, a point in
// previously free space (or behind a previously seen surface) its full range change. Rows come
// from the sensor's BeamLookup, as in the range image (range_image.hpp), columns from the
// polynomial atan2 of azimuth_time.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

struct SpeedMatrix {
  int rows = 0, cols = 0;
  /// Per pixel of the CURRENT range image: |r^k - r^{k-1}| (m per scan), or -1 when unknown (no
  /// current point, or no previous return around where it lands).
  std::vector<float> speed;
  /// Per pixel of the current image: the pixel of the previous image it lands in, or -1.
  std::vector<int> previous_pixel;
  /// Per pixel of the current image: 1 when the current point lies behind every previous return
  /// around it (the previous scan saw a surface in front of it: it was hidden then, or it moved
  /// away), 0 otherwise.
  std::vector<std::uint8_t> behind;
  [[nodiscard]] bool known(int px) const { return speed[static_cast<std::size_t>(px)] >= 0.0f; }
};

/// `current`: range image of `current_points` (both in the current frame, de-skewed);
/// `current_to_previous`: T^{k->k-1}; `previous_range`: the range channel (rows*cols, 0 = empty) of
/// the de-skewed previous scan's image in its own frame. Both must have the sensor's size; throws
/// InputError otherwise.
SpeedMatrix compute_speed_matrix(const RangeImage& current, const std::vector<Vec3>& current_points,
                                 const Pose& current_to_previous, const std::vector<float>& previous_range,
                                 const SensorConfig& sensor);

/// The pixels static_area scores: every `stride`-th pixel of a cluster (pixel_label > 0) that has a
/// point, except pixels on surfaces seen at grazing incidence (terrain left as clusters): those
/// look static with no motion whatever the motion is. Computed once per scan pair, not per candidate.
std::vector<int> static_area_pixels(const RangeImage& current, const std::vector<Vec3>& current_points,
                                    const std::vector<int>& pixel_label, int stride);

/// The surface (sum of squared ranges, a pixel's footprint grows with r^2) of `pixels` (from
/// static_area_pixels) whose speed is known and below `v_static` with the motion
/// `current_to_previous`: the score of a candidate motion when there is no prior (the static world
/// is most of a scan's surface, nearby vehicles most of its pixels).
double static_area(const RangeImage& current, const std::vector<Vec3>& current_points,
                   const std::vector<int>& pixels, const Pose& current_to_previous,
                   const std::vector<float>& previous_range, const SensorConfig& sensor, double v_static);

/// How much of the surface of `pixels` agrees with the previous range image after a motion.
struct StaticFit {
  double consistent = 0.0;  ///< surface (sum of r^2) whose speed is below the tolerance
  double compared = 0.0;    ///< surface that landed on previous returns (the rest cannot be judged)
  [[nodiscard]] double fraction() const { return compared > 0.0 ? consistent / compared : 0.0; }
};
/// static_area's measure with its denominator: the fraction of the compared surface that agrees
/// within `tolerance` (m). Previous pixels of range 0 (no return, or masked out: moving objects)
/// are not compared.
StaticFit static_fit(const RangeImage& current, const std::vector<Vec3>& current_points,
                     const std::vector<int>& pixels, const Pose& current_to_previous,
                     const std::vector<float>& previous_range, const SensorConfig& sensor, double tolerance);

}  // namespace dloam
