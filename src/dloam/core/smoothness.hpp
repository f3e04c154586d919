// Per-row point sequences of a segmented range image and their smoothness (paper eq. 14),
// with LOAM's reliability rules: points on the far side of a depth jump (occluded) and points on
// surfaces nearly parallel to the beam are marked unusable for feature selection.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/segmentation.hpp"

namespace dloam {

/// The usable pixels (ground + kept clusters) of every row, in column order; rows are
/// concatenated: row v holds entries [row_start[v], row_start[v + 1]). A row is circular
/// (column 0 follows the last column), so windows wrap around the rear of the sensor.
struct RowSequences {
  std::vector<int> row_start;        ///< rows + 1 entries
  std::vector<int> pixel;            ///< pixel index in the range image
  std::vector<int> col;              ///< column of the pixel
  std::vector<float> range;          ///< range of the pixel's point
  std::vector<float> c;              ///< smoothness (eq. 14), -1 when the row is shorter than S + 1
  std::vector<std::uint8_t> usable;  ///< 0: occluded, nearly parallel to the beam, or no c

  [[nodiscard]] std::size_t size() const { return pixel.size(); }
};

/// Reliability rules of LOAM / LeGO-LOAM (constants of the original code).
struct SmoothnessRules {
  double occlusion_jump = 0.3;   ///< m, range jump between row neighbours that marks the far side occluded
  int occlusion_max_gap = 10;    ///< columns; farther apart = a gap (empty space), not a neighbour
  double parallel_ratio = 0.02;  ///< |r_{i+-1} - r_i| > ratio * r_i on both sides -> beam nearly parallel
};

/// Builds the sequences and computes c_i = |sum_{j in S, j != i} (r_j - r_i)| / (|S| r_i)
/// with S/2 neighbours on each side (S = window size, even, >= 2). Neighbours beyond a column
/// gap (> occlusion_max_gap columns without a usable pixel: sky, removed outliers) count as
/// 2 r_i, so the last point before empty space is a silhouette edge; the occlusion and
/// parallel rules never compare across such a gap. Rows with fewer than
/// S + 2 points get no c (-1) and are unusable.
RowSequences compute_smoothness(const SegmentationResult& seg, int S, const SmoothnessRules& rules = {});

}  // namespace dloam
