// Traditional two-frame dynamic-object detection (paper III.D.3.a): a pixel is static when its
// speed (speed_matrix.hpp, eq. 13) is below v_static; a cluster is dynamic when fewer than alpha
// of its pixels with a known speed are static; pixels uncovered by an occluder that moved away (more
// than v_max behind the previous surface) do not vote. Ground pixels are re-verified: only those with a
// speed below v_ground stay static ground (the others give no feature and do not enter the map).
// Output: per-pixel masks and per-point SemanticKITTI labels (9 static, 251 moving).
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/segmentation.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

/// Per-cluster speed statistics (index = cluster label, 0 unused).
struct ClusterVotes {
  std::vector<int> known;         ///< pixels with a known speed
  std::vector<int> static_count;  ///< ... of which below v_static
  /// static_count / known, or -1 when fewer than `min_known` pixels have a known speed.
  [[nodiscard]] double static_fraction(int cluster, int min_known) const;
};

/// Pixels of known speed, and those below v_static, per cluster. A pixel whose point lies more than
/// `v_max` behind the previous scan's surface does not vote: no object moves that far in one scan, so
/// the previous scan's surface there was an occluder that has since moved (disocclusion), which says
/// nothing about this point's motion.
ClusterVotes vote_clusters(const SegmentationResult& seg, const SpeedMatrix& S, double v_static,
                           double v_max);

struct DetectionResult {
  std::vector<std::uint8_t> cluster_dynamic;  ///< per cluster label (0..m), 1 = dynamic
  std::vector<double> static_fraction;        ///< per cluster label: static pixels / known, -1 unknown
  std::vector<std::uint8_t> pixel_dynamic;    ///< rows*cols: pixel of a dynamic cluster
  std::vector<std::uint8_t> ground_rejected;  ///< rows*cols: ground pixel with speed >= v_ground
  int num_dynamic = 0;
};

/// Cluster decision (fraction of static pixels < alpha; clusters with fewer than N_min_dynamic
/// pixels of known speed stay static) and ground re-verification.
DetectionResult detect_dynamic(const SegmentationResult& seg, const SpeedMatrix& S,
                               const DetectionConfig& config);

/// Recomputes the pixel mask after cluster_dynamic changed (e.g. by the object tracker).
void update_pixel_mask(const SegmentationResult& seg, DetectionResult& det);

/// Per input point: kMovingGeneric (251) with the cluster id as instance when its pixel belongs to
/// a dynamic cluster, else kStatic (9).
std::vector<Label> point_labels(const SegmentationResult& seg, const DetectionResult& det);

}  // namespace dloam
