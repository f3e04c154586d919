// SemanticKITTI moving-object segmentation (MOS) metrics and the paper's object-level IoU (eq. 16).
//
// Point level (SemanticKITTI MOS protocol): class = label & 0xFFFF. Ground-truth classes 0
// (unlabeled) and 1 (outlier) are ignored: such points are left out of every count. Ground truth
// 251..259 is moving, every other class is static. A prediction is moving iff its class is in
// 251..259 (predicted 0/1 count as static). One confusion matrix is summed over all points of all
// scans; IoU = TP / (TP + FP + FN) of the moving class.
//
// Object level (eq. 16), per scan, then summed over scans. Objects are ground-truth instances
// (label >> 16, nonzero), grouped separately among moving and among static non-ignored points.
//  - TP: a moving GT object with more than `min_fraction` of its points predicted moving; else FN.
//    Moving points with instance 0 belong to no object and do not count here.
//  - FP: (a) a static GT instance (a parked car, ...) with more than `min_fraction` of its points
//    predicted moving; plus (b), only when the prediction carries instance ids (upper 16 bits of
//    predicted-moving points): a predicted moving instance none of whose points lies on a moving
//    GT point or on a static GT instance already counted in (a) (so no object counts twice).
//    Predicted-moving points with instance 0 on the static background form no object.
// Object IoU = TP / (TP + FP + FN).
//
// Effective features (Table III): the fraction of feature points whose GT class is not moving,
// feature points on ignored GT excluded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::eval {

/// Point-level confusion of the moving class (tn = static predicted static).
struct MosConfusion {
  std::uint64_t tp = 0, fp = 0, fn = 0, tn = 0;
  std::uint64_t ignored = 0;  ///< points with ignored GT, left out of tp/fp/fn/tn

  [[nodiscard]] double iou() const;         ///< moving IoU; NaN when tp + fp + fn = 0
  [[nodiscard]] double precision() const;   ///< tp / (tp + fp); NaN when 0/0
  [[nodiscard]] double recall() const;      ///< tp / (tp + fn); NaN when 0/0
  [[nodiscard]] double static_iou() const;  ///< tn / (tn + fp + fn)
  MosConfusion& operator+=(const MosConfusion& other);
};

struct ObjectCounts {
  std::uint64_t tp = 0, fp = 0, fn = 0;
  [[nodiscard]] double iou() const;  ///< NaN when tp + fp + fn = 0
  ObjectCounts& operator+=(const ObjectCounts& other);
};

/// Confusion of one scan. Throws InputError if the label counts differ.
MosConfusion point_confusion(const std::vector<Label>& gt, const std::vector<Label>& pred);

/// Object counts of one scan (definition above). Throws InputError if the label counts differ or
/// min_fraction is outside [0, 1).
ObjectCounts object_counts(const std::vector<Label>& gt, const std::vector<Label>& pred,
                           double min_fraction = 0.5);

/// Accumulates point and object counts over scans.
struct MosResult {
  std::size_t scans = 0;
  MosConfusion points;
  ObjectCounts objects;
};
void add_scan(MosResult& result, const std::vector<Label>& gt, const std::vector<Label>& pred,
              double min_fraction = 0.5);

struct FeatureCounts {
  std::uint64_t effective = 0;         ///< features on non-moving GT
  std::uint64_t total = 0;             ///< features on non-ignored GT
  [[nodiscard]] double ratio() const;  ///< effective / total; NaN when total = 0
  FeatureCounts& operator+=(const FeatureCounts& other);
};

/// Throws InputError if an index is out of range.
FeatureCounts count_effective_features(const std::vector<Label>& gt,
                                       const std::vector<std::size_t>& feature_indices);

}  // namespace dloam::eval
