// Static-map accuracy in the DynamicMap benchmark's terms: SA, the share of the drive's static
// places the map keeps, DA, the share of its dynamic places the map leaves out, and their
// geometric mean.
//
// The reference is every labelled point of the drive (ground truth labels, accumulated with the
// given poses) within `max_range` of its scan, in a voxel grid of `leaf`: a voxel is dynamic when
// most of its labelled points are moving (SemanticKITTI 251..259), else static; ignored classes
// (0, 1) are left out. Each map point takes the label of the nearest reference voxel (its points'
// mean) within `radius`; a reference voxel is kept when at least one map point took it.
//   SA = kept static voxels / static voxels,  DA = 1 - kept dynamic voxels / dynamic voxels.
// Map points with no reference voxel within `radius` (beyond max_range, unlabelled places) are
// counted apart and take no part in SA / DA.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::eval {

struct MapAccuracyConfig {
  double leaf = 0.2;        ///< reference voxel size (m): the map's own voxel size
  double radius = 0.2;      ///< a map point takes the nearest reference voxel within this (m), <= leaf
  double max_range = 60.0;  ///< reference points farther than this from their scan are left out (m)
};

struct MapAccuracy {
  std::uint64_t static_voxels = 0, static_kept = 0;
  std::uint64_t dynamic_voxels = 0, dynamic_kept = 0;
  std::uint64_t map_points = 0, map_static = 0, map_dynamic = 0, map_unmatched = 0;
  [[nodiscard]] double sa() const;     ///< NaN when there is no static voxel
  [[nodiscard]] double da() const;     ///< NaN when there is no dynamic voxel
  [[nodiscard]] double score() const;  ///< sqrt(SA * DA)
};

class MapAccuracyEvaluator {
 public:
  /// Throws InputError for a bad config (radius above leaf, non-positive sizes).
  explicit MapAccuracyEvaluator(const MapAccuracyConfig& config);
  /// One scan of the drive: sensor-frame points, their ground-truth labels, the scan's pose.
  /// Throws InputError when the counts differ.
  void add_scan(const std::vector<Vec3>& points, const std::vector<Label>& gt, const Pose& pose);
  /// Scores `map` (world points, the frame of the poses given to add_scan).
  [[nodiscard]] MapAccuracy evaluate(const std::vector<Vec3>& map) const;
  [[nodiscard]] std::size_t reference_voxels() const { return cells_.size(); }

 private:
  struct Cell {
    float sum[3] = {0, 0, 0};
    std::uint32_t static_count = 0, moving_count = 0;
  };
  MapAccuracyConfig config_;
  std::unordered_map<std::uint64_t, Cell> cells_;
};

}  // namespace dloam::eval
