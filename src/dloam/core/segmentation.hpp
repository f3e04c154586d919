// Segmentation module (paper III.C): projection to the range image (eq. 4-6), ground
// extraction (eq. 7) and range-image clustering of the rest, with the labels written back to
// every input point: -1 ground, 0 outlier / not in the image, 1..m clusters.
#pragma once

#include <vector>

#include "dloam/core/clustering.hpp"
#include "dloam/core/ground.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// III.C Segmentation: ground by adjacent-row pitch (eq. 7), range-image clusters.
struct SegmentationConfig : GroundConfig, ClusteringConfig {};

struct SegmentationResult {
  RangeImage image;
  std::vector<int> pixel_label;  ///< rows*cols: -1 ground, 0 empty/outlier, 1..num_clusters
  /// Per input point: its pixel's label (also for points that lost the pixel to a nearer
  /// point); 0 for points outside the image (field of view, range limits).
  std::vector<int> point_label;
  int num_clusters = 0;
  int num_ground_pixels = 0;
  Vec3 ground_normal = Vec3::UnitZ();  ///< unit, pointing up; +z when no plane was found
  double ground_height = 0.0;          ///< sensor height above the ground plane (m)
  bool ground_plane_valid = false;

  [[nodiscard]] bool is_ground_pixel(int px) const {
    return pixel_label[static_cast<std::size_t>(px)] == kGroundLabel;
  }
  [[nodiscard]] bool is_cluster_pixel(int px) const { return pixel_label[static_cast<std::size_t>(px)] > 0; }
};

/// Deterministic. Throws InputError when the sensor model is inconsistent.
SegmentationResult segment(const std::vector<Vec3>& points, const SensorConfig& sensor,
                           const SegmentationConfig& config);

/// Same on an existing projection of `points` (e.g. a de-skewed scan projected by the caller).
SegmentationResult segment_image(const std::vector<Vec3>& points, RangeImage image,
                                 const SensorConfig& sensor, const SegmentationConfig& config);

}  // namespace dloam
