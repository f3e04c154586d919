#include "dloam/pipeline/pipeline.hpp"

#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/segmentation.hpp"

namespace dloam {

namespace {
template <class T>
std::vector<std::size_t> to_indices(const std::vector<T>& v) {
  return {v.begin(), v.end()};
}
}  // namespace

Pipeline::Pipeline(const PipelineConfig& config)
    : config_(config), odometry_(config.odometry), mapper_(config.mapping) {
  config_.sensor.validate();
}

ScanResult Pipeline::process(const PointCloud& cloud) {
  ScanResult out;
  out.index = count_;
  ScopedTimer total(out.times, Module::kTotal);

  // Motion-distortion removal with the constant-velocity prediction (eq. 12), reference = mid-sweep.
  std::vector<Vec3> points;
  {
    ScopedTimer t(out.times, Module::kDeskew);
    points = cloud.xyz;
    correct_vertical_angle(points, config_.sensor.vertical_angle_correction_deg);
    if (config_.deskew.enabled && config_.deskew.time_source != "none" && count_ > 0) {
      const auto times = point_times(cloud, config_.deskew.time_source == "auto");
      points = deskew(points, times, velocity_);
    }
  }

  SegmentationResult seg;
  {
    ScopedTimer t(out.times, Module::kSegmentation);
    seg = segment(points, config_.sensor, config_.segmentation);
  }

  FeatureSet features;
  {
    ScopedTimer t(out.times, Module::kFeatures);
    features = extract_features(points, seg, config_.features, nullptr);
  }
  out.edge_features = to_indices(features.F_e_index);
  out.plane_features = to_indices(features.F_p_index);

  {
    ScopedTimer t(out.times, Module::kOdometry);
    FeatureSource sharp{features.f_e, features.f_p, {}, {}};
    const auto odo = odometry_.process(sharp, features.F_e, features.F_p, velocity_);
    odometry_pose_ = normalized(odometry_pose_ * odo.motion);
    out.degenerate = odo.plane_step.degenerate || odo.edge_step.degenerate;
  }
  out.odometry_pose = odometry_pose_;

  // Scan-to-map at the mapping rate; transform integration in between.
  const int every = std::max(1, config_.mapping.every_n_scans);
  if (count_ % static_cast<std::size_t>(every) == 0) {
    ScopedTimer t(out.times, Module::kMapping);
    FeatureSource all{features.F_e, features.F_p, {}, {}};
    const auto m = mapper_.process(count_, all, correction_ * odometry_pose_);
    correction_ = normalized(m.pose * odometry_pose_.inverse());
    out.mapped = true;
    out.keyframe = m.keyframe;
    if (m.keyframe) mapper_.add_to_global_map(points, m.pose);
  }
  out.pose = normalized(correction_ * odometry_pose_);
  velocity_ = count_ > 0 ? last_pose_.inverse() * out.pose : Pose::Identity();
  last_pose_ = out.pose;
  ++count_;
  return out;
}

}  // namespace dloam
