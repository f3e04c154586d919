#include "dloam/pipeline/pipeline.hpp"

#include <numeric>
#include <stdexcept>

#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/weight_compensation.hpp"

namespace dloam {

namespace {
constexpr double kRedeskewRotation = 0.5 * M_PI / 180.0;  // rad
constexpr double kRedeskewTranslation = 0.1;              // m

template <class T>
std::vector<std::size_t> to_indices(const std::vector<T>& v) {
  return {v.begin(), v.end()};
}

/// Dynamic points never enter the map; neither do ground points that failed the re-verification
/// nor outliers (clusters too small for the detector to judge, often fragments of moving objects).
std::vector<std::size_t> static_points(const std::vector<Label>& labels, const SegmentationResult& seg,
                                       const std::vector<std::uint8_t>& excluded_pixels) {
  std::vector<std::size_t> out;
  out.reserve(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const int px = seg.image.pixel_of_point(i);
    if (semantic::is_moving(labels[i]) || seg.point_label[i] == kOutlierLabel) continue;
    if (px >= 0 && excluded_pixels[static_cast<std::size_t>(px)]) continue;
    out.push_back(i);
  }
  return out;
}
}  // namespace

Pipeline::Pipeline(const PipelineConfig& config)
    : config_(config), odometry_(config.odometry), mapper_(config.mapping, config.sensor.scan_rate_hz) {
  config_.sensor.validate();
  if (config_.detection.detector == "cnn")
    throw std::invalid_argument(
        "detection.detector: the CNN detector is not available yet; use none or geometric");
  if (config_.detection.detector == "geometric") dynamic_ = std::make_unique<DynamicStage>(config_);
}

ScanResult Pipeline::process(const PointCloud& cloud) {
  ScanResult out;
  out.index = count_;
  ScopedTimer total(out.times, Module::kTotal);

  // Motion-distortion removal with the constant-velocity prediction (eq. 12), reference = mid-sweep.
  std::vector<Vec3> points, raw;
  std::vector<double> times;
  {
    ScopedTimer t(out.times, Module::kDeskew);
    points = cloud.xyz;
    correct_vertical_angle(points, config_.sensor.vertical_angle_correction_deg);
    if (config_.deskew.enabled && config_.deskew.time_source != "none") {
      if (count_ > 0 || dynamic_) times = point_times(cloud, config_.deskew.time_source == "auto");
      raw = points;
      if (count_ > 0) points = deskew(points, times, velocity_);
    } else if (dynamic_) {
      raw = points;
    }
  }

  SegmentationResult seg;
  {
    ScopedTimer t(out.times, Module::kSegmentation);
    seg = segment(points, config_.sensor, config_.segmentation);
  }

  // Dynamic-object detection (III.D): T_coarse, re-de-skew, speed matrix, labels, feature mask.
  DynamicOutput dyn;
  if (dynamic_) {
    ScopedTimer t(out.times, Module::kDetection);
    dyn = dynamic_->process(raw, times, std::move(points), seg, velocity_);
    points = std::move(dyn.points);
    out.labels = std::move(dyn.labels);
    out.num_dynamic = dyn.num_dynamic;
    out.pseudo_static = dyn.type2;
    out.coarse_valid = dyn.coarse_valid;
  }

  FeatureSet features;
  {
    ScopedTimer t(out.times, Module::kFeatures);
    features = extract_features(points, seg, config_.features, dynamic_ ? &dyn.mask : nullptr);
  }
  out.edge_features = to_indices(features.F_e_index);
  out.plane_features = to_indices(features.F_p_index);
  out.n_edges = features.F_e.size();
  out.n_planes = features.F_p.size();

  {
    ScopedTimer t(out.times, Module::kOdometry);
    FeatureSource sharp{features.f_e, features.f_p, {}, {}};
    if (dynamic_ && config_.odometry.weight_compensation) {  // eq. 15
      sharp.edge_weights = compensated_weights(features.f_e_index, seg.image, dyn.column_distance);
      sharp.plane_weights = compensated_weights(features.f_p_index, seg.image, dyn.column_distance);
    }
    const bool reject = dynamic_ != nullptr;
    auto odo = odometry_.estimate(sharp, velocity_, reject);
    if (!times.empty() && count_ > 0) {
      // The constant-velocity de-skew is wrong where the turn rate changes (start and end of a
      // turn): de-skew the features again with the motion just estimated, and estimate once more
      // when that motion differs much from the prediction. The map and the next scan's target get
      // the refined features.
      const Pose change = velocity_.inverse() * odo.motion;
      if (rotation_angle(change) > kRedeskewRotation || translation_norm(change) > kRedeskewTranslation) {
        sharp.edges = deskew(raw, times, features.f_e_index, odo.motion);
        sharp.planes = deskew(raw, times, features.f_p_index, odo.motion);
        odo = odometry_.estimate(sharp, odo.motion, reject);
      }
      features.F_e = deskew(raw, times, features.F_e_index, odo.motion);
      features.F_p = deskew(raw, times, features.F_p_index, odo.motion);
    }
    odometry_.set_previous(features.F_e, features.F_p);
    out.rejected_features = odo.rejected;
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
    out.loop_closed = m.loop.has_value();
    if (m.keyframe && dynamic_) {
      // The first scan has no speed matrix: its moving objects are unknown, it adds no map points.
      if (dyn.checked) out.map_points = static_points(out.labels, seg, dyn.mask.excluded);
      std::vector<Vec3> kept;
      kept.reserve(out.map_points.size());
      for (std::size_t i : out.map_points) kept.push_back(points[i]);
      mapper_.add_to_global_map(kept, m.pose);
    } else if (m.keyframe) {
      out.map_points.resize(points.size());
      std::iota(out.map_points.begin(), out.map_points.end(), std::size_t{0});
      mapper_.add_to_global_map(points, m.pose);
    }
  }
  out.pose = normalized(correction_ * odometry_pose_);
  // A loop closure moves the pose at once: that jump is not motion (keep the last velocity).
  if (!out.loop_closed) velocity_ = count_ > 0 ? last_pose_.inverse() * out.pose : Pose::Identity();
  last_pose_ = out.pose;
  ++count_;
  return out;
}

}  // namespace dloam
