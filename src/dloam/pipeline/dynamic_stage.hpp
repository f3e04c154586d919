// The pipeline's dynamic-object stage (paper III.D, geometric detector): pre-registration of the
// current scan's pole / plane objects against the previous scan's (T_coarse), de-skew of the
// current scan with T_coarse and of the previous one with the refined motion (eq. 12), the speed
// matrix (eq. 13), the two-frame cluster detector with ground re-verification, the pseudo-static
// object tracker, and what the later modules need: the feature mask, eq. 15's column distances
// and per-point labels. Keeps the previous scan between calls.
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/object_tracker.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

struct DynamicOutput {
  std::vector<Vec3> points;          ///< current scan de-skewed with T_coarse (same order as input)
  FeatureMask mask;                  ///< dynamic / rejected-ground pixels, type-2 pseudo-static pixels
  std::vector<Label> labels;         ///< per input point: 9 static, 251 moving
  std::vector<int> column_distance;  ///< eq. 15: columns to the nearest dynamic pixel (-1: none)
  Pose T_coarse = Pose::Identity();  ///< current -> previous scan frame
  bool coarse_valid = false;
  bool checked = false;  ///< a previous scan existed: the labels come from a speed matrix
  int num_dynamic = 0, type1 = 0, type2 = 0;
};

class DynamicStage {
 public:
  explicit DynamicStage(const PipelineConfig& config) : config_(config) {}

  /// `raw`: the scan (vertical-angle corrected, not de-skewed) and its point times; `deskewed`:
  /// the scan de-skewed with `predicted` (the constant-velocity motion, also the refined motion of
  /// the previous sweep), segmented into `seg`.
  DynamicOutput process(const std::vector<Vec3>& raw, const std::vector<double>& times,
                        std::vector<Vec3> deskewed, const SegmentationResult& seg, const Pose& predicted);

 private:
  PipelineConfig config_;
  bool have_previous_ = false;
  std::vector<float> previous_range_;  ///< previous scan's range image (its final de-skew, own frame)
  std::unique_ptr<FeatureMap> previous_objects_;
  ObjectTracker tracker_;
};

}  // namespace dloam
