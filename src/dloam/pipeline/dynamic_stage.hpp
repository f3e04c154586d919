// The pipeline's dynamic-object stage (paper III.D, geometric detector): pre-registration of the
// current scan's pole / plane objects against the previous scan's (T_coarse; dloam refines it by
// aligning the two range images, core/range_alignment.hpp), de-skew of the
// current scan with T_coarse and of the previous one with the refined motion (eq. 12), the speed
// matrix (eq. 13), the two-frame cluster detector with ground re-verification, the pseudo-static
// object tracker, and what the later modules need: the feature mask, eq. 15's column distances
// and per-point labels. Keeps the previous scan between calls. The first scan pair has no motion
// prior: T_coarse comes from a search over forward translation, and both scans of the pair are
// de-skewed with it before the refinement (the first scan was never de-skewed).
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/deskew.hpp"
#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/motion_model.hpp"
#include "dloam/core/object_tracker.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/core/range_alignment.hpp"
#include "dloam/pipeline/cnn_stage.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

/// The motion model's view of the step to the current scan.
struct StepPrior {
  Pose predicted = Pose::Identity();  ///< the constant-velocity prediction of the step
  ScanInterval interval;              ///< time since the previous scan, sweep duration
  MotionGate gate;                    ///< how far T_coarse may depart from the prediction
  double search_range = 4.0;          ///< m: forward translation searched when there is no prior
  double yaw_range = 0.0;             ///< rad: turns searched when there is no prior (at most pi)
  /// The step check's target (the previous scan's ranges), its probe pixels of this scan and the
  /// fit T_coarse must reach (step_fit.hpp) for the speed matrix to be trusted; null or 0: always
  /// trusted.
  const std::vector<float>* previous_range = nullptr;
  const std::vector<int>* probe = nullptr;
  double min_fit = 0.0;
};

struct DynamicOutput {
  std::vector<Vec3> points;          ///< current scan de-skewed with T_coarse (same order as input)
  FeatureMask mask;                  ///< dynamic / rejected-ground pixels, type-2 pseudo-static pixels
  std::vector<Label> labels;         ///< per input point: 9 static, 251 moving
  std::vector<int> column_distance;  ///< eq. 15: columns to the nearest dynamic pixel (-1: none)
  Pose T_coarse = Pose::Identity();  ///< current -> previous scan frame
  bool coarse_valid = false;
  bool checked = false;  ///< a previous scan existed: the labels come from a speed matrix
  int num_dynamic = 0, type1 = 0, type2 = 0;
  /// T_coarse fitted the previous scan worse than StepPrior::min_fit: the speed matrix would show the
  /// registration error as motion, so nothing was marked moving.
  bool suspended = false;
};

class DynamicStage {
 public:
  /// `cnn`: the learned segmenter when the detector is "cnn" (null: the geometric detector).
  explicit DynamicStage(const PipelineConfig& config, std::shared_ptr<MovingSegmenter> cnn = nullptr)
      : config_(config) {
    if (cnn) cnn_ = std::make_unique<CnnStage>(std::move(cnn), config.sensor);
  }

  /// `raw`: the scan (vertical-angle corrected, not de-skewed) and its point times; `deskewed`:
  /// the scan de-skewed with the prediction of `prior` (the constant-velocity motion), segmented
  /// into `seg`.
  DynamicOutput process(const std::vector<Vec3>& raw, const std::vector<double>& times,
                        std::vector<Vec3> deskewed, const SegmentationResult& seg, const StepPrior& prior,
                        const std::vector<float>& intensity = {});
  /// The odometry's pose of the scan just processed (the CNN's bags use the pipeline's own poses).
  void refine_pose(const Pose& pose) {
    if (cnn_) cnn_->refine_latest(pose);
  }

 private:
  /// The first pair: T_coarse without a prior (search_forward_translation scored by the static
  /// cluster pixels, then the object ICP); re-de-skews the first scan (range image, objects)
  /// and the current objects with it. Returns the coarse result.
  CoarseResult first_pair(const std::vector<Vec3>& raw, const std::vector<double>& times,
                          const std::vector<Vec3>& deskewed, const SegmentationResult& seg,
                          const StepPrior& prior, ObjectSet& objects);
  void remember_range(const RangeImage& image, const std::vector<Vec3>& points);

  PipelineConfig config_;
  bool have_previous_ = false;
  bool first_pair_done_ = false;
  /// The first scan (raw, times, segmentation), kept until the first pair is processed.
  std::vector<Vec3> first_raw_;
  std::vector<double> first_times_;
  std::unique_ptr<SegmentationResult> first_seg_;
  /// The previous scan's range image (its final de-skew, own frame): ranges and points.
  VertexMap previous_vertices_;
  std::vector<int> pixel_scratch_;  ///< remember_range's pixel per point, kept between scans
  std::unique_ptr<FeatureMap> previous_objects_;
  ObjectTracker tracker_;
  std::unique_ptr<CnnStage> cnn_;
};

}  // namespace dloam
