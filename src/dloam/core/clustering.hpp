// Range-image clustering of non-ground pixels (Bogoslavskyi & Stachniss, "Fast range image-based
// segmentation of sparse 3D laser scans", as used by LeGO-LOAM and paper III.C): breadth-first
// search over 4-neighbours (columns wrap around), two neighbours join when the angle
// beta = atan2(d2 sin(a), d1 - d2 cos(a)) exceeds segment_theta_deg, with d1 / d2 the larger /
// smaller range and a the angle between the two beams (horizontal step, or the actual
// elevation gap between the two rows for non-uniform beams). A neighbour may lie one empty pixel
// away (then a is doubled): ~20 % of a KITTI HDL-64E range image is holes, which would otherwise
// shatter objects (measured on kitti-raw-0005: docs/results.md, detector parameters).
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam {

/// III.C range-image clustering.
struct ClusteringConfig {
  double segment_theta_deg =
      10.0;  ///< angle-based clustering threshold (Bogoslavskyi's 10; LeGO-LOAM's 60 shatters 64-beam scans)
  int N_min_cluster = 30;       ///< clusters with fewer points are outliers (LeGO-LOAM's 30)
  int N_min_cluster_small = 5;  ///< ... unless they have this many points spanning
  int N_min_cluster_rows = 3;   ///< ... at least this many rows
};

/// Pixel labels of a segmented range image.
inline constexpr int kGroundLabel = -1;  ///< ground pixel
inline constexpr int kOutlierLabel = 0;  ///< empty pixel, or a rejected (too small) cluster

struct ClusterResult {
  std::vector<int> label;  ///< rows*cols: -1 ground, 0 empty/outlier, 1..num_clusters kept clusters
  int num_clusters = 0;
};

/// Clusters the valid non-ground pixels. A cluster is kept when it has >= N_min_cluster pixels,
/// or >= N_min_cluster_small pixels spanning >= N_min_cluster_rows rows; kept clusters are
/// numbered 1..m in the order of their first pixel (row-major scan), so the result is
/// deterministic. `ground_mask` (rows*cols, nonzero = ground) may be empty.
ClusterResult cluster_range_image(const RangeImage& image, const std::vector<std::uint8_t>& ground_mask,
                                  const SensorConfig& sensor, const ClusteringConfig& config);

}  // namespace dloam
