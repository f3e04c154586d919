#include "dloam/pipeline/pipeline.hpp"

#include <chrono>
#include <numeric>
#include <stdexcept>

#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/preregistration.hpp"
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

Pipeline::Pipeline(const PipelineConfig& config, std::shared_ptr<MovingSegmenter> cnn)
    : config_(config), odometry_(config.odometry), mapper_(config.mapping, config.sensor.scan_rate_hz) {
  config_.sensor.validate();
  if (config_.detection.detector == "auto") config_.detection.detector = cnn ? "cnn" : "geometric";
  if (config_.detection.detector == "cnn") {
    if (!cnn)
      throw std::invalid_argument(
          "detection.detector is cnn but no model was loaded (detection.model_path; a build with LibTorch)");
    dynamic_ = std::make_unique<DynamicStage>(config_, std::move(cnn));
  }
  if (config_.detection.detector == "geometric") dynamic_ = std::make_unique<DynamicStage>(config_);
  if (config_.mapping.latency_scans < 0 || config_.mapping.latency_scans > config_.mapping.every_n_scans)
    throw std::invalid_argument("mapping.latency_scans must be in [0, mapping.every_n_scans]");
}

Pipeline::~Pipeline() {
  if (job_ && job_->output.valid()) job_->output.wait();
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
      times = point_times(cloud, config_.deskew.time_source == "auto");  // scan 0: de-skewed at scan 1
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
    dyn = dynamic_->process(raw, times, std::move(points), seg, velocity_, cloud.intensity);
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
    // T_coarse (static poles / planes, III.D.1) is the initial guess when valid; the features
    // were de-skewed with it.
    const Pose initial = dynamic_ && dyn.coarse_valid ? dyn.T_coarse : velocity_;
    // T_coarse passed the motion gate (and is aligned on the range images when refined): an
    // odometry that moves farther than the gate from it has slid along repeated structure (a
    // highway's guard-rail posts, one spacing along) and is not believed.
    const auto believe = [&](auto odometry) {
      if (dynamic_ && dyn.coarse_valid &&
          !within_motion_gate(initial.inverse() * odometry.motion, config_.preregistration))
        odometry.motion = initial;
      return odometry;
    };
    const bool first_pair = first_ && !first_->raw.empty();
    // Scan 1 was de-skewed with T_coarse: so is its target, the first scan. Registering a
    // de-skewed scan to a skewed one is biased by the sweep's motion (a first step up to 6 cm short
    // at 25 km/h, which the map built on the first scan then keeps).
    if (first_pair && dynamic_ && dyn.coarse_valid) deskew_first_scan(initial);
    auto odo = believe(odometry_.estimate(sharp, initial, reject));
    if (first_pair) {
      // The first motion is known; de-skew the first scan with it (constant velocity) and
      // estimate again against the corrected target.
      deskew_first_scan(odo.motion);
      odo = believe(odometry_.estimate(sharp, odo.motion, reject));
      first_->raw.clear();  // done
    }
    if (!times.empty() && count_ > 0) {
      // The constant-velocity de-skew is wrong where the turn rate changes (start and end of a
      // turn): de-skew the features again with the motion just estimated, and estimate once more
      // when that motion differs much from the prediction. The map and the next scan's target get
      // the refined features.
      const Pose change = initial.inverse() * odo.motion;
      if (rotation_angle(change) > kRedeskewRotation || translation_norm(change) > kRedeskewTranslation) {
        sharp.edges = deskew(raw, times, features.f_e_index, odo.motion);
        sharp.planes = deskew(raw, times, features.f_p_index, odo.motion);
        odo = believe(odometry_.estimate(sharp, odo.motion, reject));
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
  if (dynamic_) dynamic_->refine_pose(odometry_pose_);

  odometry_poses_.push_back(odometry_pose_);

  // Scan-to-map at the mapping rate, on a worker thread; transform integration in between.
  std::vector<std::size_t> map_points;
  if (dynamic_) {
    // The first scan has no speed matrix: its moving objects are unknown, it adds no map points.
    if (dyn.checked) map_points = static_points(out.labels, seg, dyn.mask.excluded);
  } else {
    map_points.resize(points.size());
    std::iota(map_points.begin(), map_points.end(), std::size_t{0});
  }
  map_scan(out, features, points, std::move(map_points), raw, times);
  out.pose = normalized(correction_ * odometry_pose_);
  // The constant-velocity prediction is the odometry's last motion: mapping corrections (and loop
  // closures) move the integrated pose in jumps when they arrive, which are not motion.
  velocity_ = count_ > 0 ? odometry_poses_[count_ - 1].inverse() * odometry_pose_ : Pose::Identity();
  last_pose_ = out.pose;
  ++count_;
  return out;
}

void Pipeline::map_scan(ScanResult& out, const FeatureSet& features, const std::vector<Vec3>& points,
                        std::vector<std::size_t> map_points, const std::vector<Vec3>& raw,
                        const std::vector<double>& times) {
  if (job_ && count_ >= job_->scan + static_cast<std::size_t>(config_.mapping.latency_scans))
    integrate_job(&out);
  if (first_) {  // scan 1: the (de-skewed) first scan is mapped first, at once
    start_job(std::move(first_->input));
    first_.reset();
    integrate_job(&out);
  }
  const auto every = static_cast<std::size_t>(std::max(1, config_.mapping.every_n_scans));
  if (count_ % every != 0) return;
  if (job_) integrate_job(&out);  // never two jobs in flight

  MappingInput in;
  in.scan = count_;
  in.features = {features.F_e, features.F_p, {}, {}};
  in.predicted = normalized(correction_ * odometry_pose_);
  in.keyframe = mapper_.needs_keyframe(in.predicted);
  out.mapped = true;
  out.keyframe = in.keyframe;
  // A keyframe whose scan gave no map points (the first scan with a detector on: its moving
  // objects are unknown) takes those of the next mapped scan that has some; a vehicle standing
  // still makes no second keyframe and would map nothing.
  const bool fill = !in.keyframe && keyframe_without_points_ && !map_points.empty();
  if (in.keyframe || fill) {
    out.map_points = std::move(map_points);
    in.points.reserve(out.map_points.size());
    for (std::size_t i : out.map_points) in.points.push_back(points[i]);
    keyframe_without_points_ = in.keyframe && out.map_points.empty();
  }
  if (count_ == 0) {  // wait for the first motion (scan 1) to de-skew it
    first_.emplace(FirstScan{});  // not emplace(): clang rejects it for a nested struct with initialisers
    if (!times.empty()) {
      first_->raw = raw;
      first_->times = times;
      first_->F_e_index = features.F_e_index;
      first_->F_p_index = features.F_p_index;
      first_->map_points = out.map_points;
    }
    first_->input = std::move(in);
    return;
  }
  start_job(std::move(in));
  if (config_.mapping.latency_scans == 0) integrate_job(&out);
}

void Pipeline::deskew_first_scan(const Pose& motion) {
  FirstScan& f = *first_;
  f.input.features.edges = deskew(f.raw, f.times, f.F_e_index, motion);
  f.input.features.planes = deskew(f.raw, f.times, f.F_p_index, motion);
  const std::vector<Vec3> points = deskew(f.raw, f.times, motion);
  for (std::size_t j = 0; j < f.map_points.size(); ++j) f.input.points[j] = points[f.map_points[j]];
  odometry_.set_previous(f.input.features.edges, f.input.features.planes);
}

void Pipeline::start_job(MappingInput input) {
  Job job;
  job.scan = input.scan;
  job.odometry_pose = odometry_poses_[input.scan];
  job.output = std::async(std::launch::async, [this, in = std::move(input)] {
    const auto start = std::chrono::steady_clock::now();
    MappingOutput o;
    const std::string where = "mapping of scan " + std::to_string(in.scan) + ": ";
    try {
      o.result = mapper_.process(in.scan, in.features, in.predicted, in.keyframe);
      if (in.keyframe) {
        mapper_.add_to_global_map(in.points);
      } else if (!in.points.empty()) {  // the points of a keyframe that had none (map_scan)
        mapper_.add_to_global_map(in.points, o.result.pose);
      }
    } catch (const InputError& e) {
      throw InputError(where + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error(where + e.what());
    }
    o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return o;
  });
  job_ = std::move(job);
}

void Pipeline::integrate_job(ScanResult* out) {
  if (!job_) return;
  // The job leaves job_ before get() rethrows its exception: a failed job is not joined twice.
  Job job = std::move(*job_);
  job_.reset();
  const MappingOutput o = job.output.get();  // rethrows the job's exception
  correction_ = normalized(o.result.pose * job.odometry_pose.inverse());
  mapped_.emplace_back(job.scan, o.result.pose);
  if (out) {
    out->loop_closed = out->loop_closed || o.result.loop.has_value();
    out->times[Module::kMapping] += o.ms;
  }
}

void Pipeline::finish() {
  if (first_) {  // a single scan: mapped as it is
    start_job(std::move(first_->input));
    first_.reset();
  }
  integrate_job(nullptr);
}

std::vector<Vec3> Pipeline::global_map() {
  finish();
  return mapper_.global_map();
}

std::vector<Pose> Pipeline::trajectory() {
  finish();
  std::vector<Pose> out(odometry_poses_.size(), Pose::Identity());
  Pose correction = Pose::Identity();
  std::size_t j = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (; j < mapped_.size() && mapped_[j].first <= i; ++j)
      correction = mapped_[j].second * odometry_poses_[mapped_[j].first].inverse();
    out[i] = normalized(correction * odometry_poses_[i]);
  }
  return mapper_.corrected_trajectory(out);
}

}  // namespace dloam
