// The CNN detector inside the pipeline (paper III.D.3.b): keeps the m most recent scans with the
// pipeline's own poses, builds the current scan's range image bag (range_image_bag.hpp) with the
// pose predicted by T_coarse, asks the learned segmenter for per-pixel moving probabilities and
// turns them into the same cluster decision as the geometric detector (cnn_decision.hpp). Until m
// scans are kept the bag lacks speed images and the two-frame detector decides (dynamic_stage).
#pragma once

#include <memory>
#include <vector>

#include "dloam/core/cnn_decision.hpp"
#include "dloam/core/moving_segmenter.hpp"
#include "dloam/core/range_image_bag.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

class CnnStage {
 public:
  CnnStage(std::shared_ptr<MovingSegmenter> net, const SensorConfig& sensor)
      : net_(std::move(net)), history_(net_->m(), sensor) {}

  /// `points`: the current scan de-skewed (with T_coarse), projected into seg.image; `range`: its
  /// range channel (rows*cols); `T_coarse`: current -> previous scan frame; `speed1`: the speed
  /// matrix against the previous scan with T_coarse when already computed (null: computed here).
  DetectionResult process(const SegmentationResult& seg, const std::vector<Vec3>& points,
                          const std::vector<float>& intensity, std::vector<float> range, const Pose& T_coarse,
                          const DetectionConfig& config, const std::vector<float>* speed1 = nullptr);
  /// True once m scans are kept: the bag of the next scan has all its speed images.
  [[nodiscard]] bool ready() const { return history_.size() >= static_cast<std::size_t>(history_.m()); }
  /// Keeps the scan for the next bags without running the network (another detector decided it).
  void remember(std::vector<float> range, const Pose& T_coarse);
  /// The refined pose of the scan just processed (the odometry's), for the next bags.
  void refine_latest(const Pose& pose);

 private:
  /// World pose of the current scan: the previous one's moved by T_coarse (identity for the first).
  [[nodiscard]] Pose pose_of(const Pose& T_coarse) const {
    return first_ ? Pose::Identity() : latest_ * T_coarse;
  }
  void push(std::vector<float> range, const Pose& pose);

  std::shared_ptr<MovingSegmenter> net_;
  ScanHistory history_;
  Pose latest_ = Pose::Identity();
  bool first_ = true;
};

}  // namespace dloam
