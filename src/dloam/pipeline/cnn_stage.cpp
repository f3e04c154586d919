#include "dloam/pipeline/cnn_stage.hpp"

namespace dloam {

DetectionResult CnnStage::process(const SegmentationResult& seg, const std::vector<Vec3>& points,
                                  const std::vector<float>& intensity, std::vector<float> range,
                                  const Pose& T_coarse, const DetectionConfig& config,
                                  const std::vector<float>* speed1) {
  const Pose pose = pose_of(T_coarse);
  const RangeImageBag bag = history_.bag(seg.image, points, intensity, pose, first_ ? nullptr : speed1);
  DetectionResult d = decide_from_probability(seg, net_->moving_probability(bag), config);
  push(std::move(range), pose);
  return d;
}

void CnnStage::remember(std::vector<float> range, const Pose& T_coarse) {
  push(std::move(range), pose_of(T_coarse));
}

void CnnStage::push(std::vector<float> range, const Pose& pose) {
  history_.push(std::move(range), pose);
  latest_ = pose;
  first_ = false;
}

void CnnStage::refine_latest(const Pose& pose) {
  latest_ = pose;
  history_.set_latest_pose(pose);
}

}  // namespace dloam
