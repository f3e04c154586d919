#include "dloam/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>

#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/core/weight_compensation.hpp"
#include "dloam/pipeline/detector_choice.hpp"
#include "dloam/pipeline/step_fit.hpp"

namespace dloam {

namespace {
/// Relative difference between a scan interval and the sweep duration below which they are equal.
constexpr double kStampJitter = 1e-4;
/// A search result replaces the prediction only when it fits this much more of the surface.
constexpr double kSearchMargin = 0.05;
/// Probe points registered per candidate of a step search.
constexpr std::size_t kSearchPoints = 500;
/// The prediction is searched around when it fits less than this fraction of what the recent
/// estimates fit, and a search result is taken only when it fits at least kPriorFitRatio of it.
constexpr double kSearchFitRatio = 0.7;
constexpr double kPriorFitRatio = 0.8;
/// A step whose estimate fits less than this fraction of that is reported as not estimated.
constexpr double kLostFitRatio = 0.5;
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

MappingConfig resolved_mapping(const PipelineConfig& config) {
  MappingConfig m = config.mapping;
  m.edge_line_ratio =
      edge_line_ratio_for(m.edge_line_ratio, config.sensor.N_scan, config.motion.platform == "car");
  return m;
}
}  // namespace

Pipeline::Pipeline(const PipelineConfig& config, std::shared_ptr<MovingSegmenter> cnn)
    : config_(config),
      odometry_(config.odometry, config.degeneracy),
      mapper_(resolved_mapping(config), config.sensor.scan_rate_hz, config.degeneracy),
      motion_(config.motion) {
  config_.sensor.validate();
  CnnModelInfo given;  // a segmenter handed over is taken to fit the sensor
  given.available = cnn != nullptr;
  given.missing_reason = "none was given to the Pipeline: dloam/run/detector_setup.hpp loads it";
  config_.detection.detector =
      choose_detector(config_.detection.detector, given, config_.sensor, config_.motion.platform).detector;
  if (config_.detection.detector == Detector::kCnn)
    dynamic_ = std::make_unique<DynamicStage>(config_, std::move(cnn));
  if (config_.detection.detector == Detector::kGeometric) dynamic_ = std::make_unique<DynamicStage>(config_);
  if (config_.mapping.latency_scans < 0 || config_.mapping.latency_scans > config_.mapping.every_n_scans)
    throw std::invalid_argument("mapping.latency_scans must be in [0, mapping.every_n_scans]");
}

Pipeline::~Pipeline() {
  if (job_ && job_->output.valid()) job_->output.wait();
}

ScanInterval Pipeline::interval_of(const PointCloud& cloud, ScanResult& out) {
  ScanInterval interval;
  interval.sweep = 1.0 / config_.sensor.scan_rate_hz;
  interval.dt = interval.sweep;
  out.stamp = cloud.stamp.value_or(static_cast<double>(count_) * interval.sweep);
  if (cloud.stamp && last_stamp_) {
    interval.dt = *cloud.stamp - *last_stamp_;
    if (!(interval.dt > 0.0))
      throw InputError("scan " + std::to_string(count_) + ": its time (" + std::to_string(*cloud.stamp) +
                       " s) is not after the previous scan's (" + std::to_string(*last_stamp_) + " s)");
    // Recorders stamp with jitter (and a stamp stored as seconds since the epoch keeps only a
    // fraction of a microsecond): an interval within kStampJitter of one sweep is one sweep, so a
    // drive gives the same poses from a folder with times.txt and from a bag of the same scans.
    if (std::abs(interval.dt - interval.sweep) < kStampJitter * interval.sweep) interval.dt = interval.sweep;
  }
  if (cloud.stamp) last_stamp_ = cloud.stamp;
  if (config_.deskew.acceleration) {
    interval.previous_velocity = motion_.twist();
    interval.previous_dt = motion_.twist_dt();
    interval.max_acceleration = config_.motion.max_acceleration;
    interval.max_angular_acceleration = config_.motion.max_angular_acceleration_deg * M_PI / 180.0;
  }
  if (count_ > 0) {
    out.dt = interval.dt;
    out.missed_scans = interval.missed_scans();
  }
  return interval;
}

double Pipeline::consistency(const SegmentationResult& seg, const std::vector<Vec3>& points,
                             const std::vector<int>& probe, const Pose& T, double tolerance) const {
  return step_fit(seg, points, probe, T, previous_range_, config_.sensor, tolerance);
}

bool Pipeline::check_prior(StepPrior& prior, const SegmentationResult& seg, const std::vector<Vec3>& points,
                           const std::vector<int>& probe, ScanResult& out) {
  out.prior_fitness = consistency(seg, points, probe, prior.predicted, kProbeInlier);
  // The first pair with a detector: its own search (DynamicStage) scores the static-looking
  // clusters without registering anything, which traffic moving with the sensor cannot win.
  if (!motion_.known() && dynamic_) return false;
  const bool trusted = motion_.known() && out.prior_fitness >= kSearchFitRatio * fit_reference_;
  if (trusted || !config_.motion.step_search) return false;
  // The search source: the probe points, thinned.
  FeatureSource source;
  const std::size_t step = std::max<std::size_t>(1, probe.size() / kSearchPoints);
  for (std::size_t k = 0; k < probe.size(); k += step)
    source.planes.push_back(
        points[static_cast<std::size_t>(seg.image.point_of_pixel[static_cast<std::size_t>(probe[k])])]);
  const FeatureMap* previous = odometry_.previous();
  if (!previous) return false;
  const bool known = motion_.known();
  auto search = [&](bool gated) {
    StepSearchOptions options;
    options.max_rotation = gated ? prior.gate.max_rotation : prior.yaw_range;
    options.max_translation = gated ? prior.gate.max_translation : prior.search_range;
    const StepSearchResult r = search_step(
        source, *previous, {gated ? prior.predicted : Pose::Identity()}, options,
        [&](const Pose& T, double tolerance) { return consistency(seg, points, probe, T, tolerance); });
    out.search_candidates += r.candidates;
    return r;
  };
  // The result must fit clearly better than the prediction, and (with a velocity) about as well as
  // the recent steps: in scenes where little of the surface is static (a highway full of traffic)
  // the score cannot tell motions apart, and the prediction is the better guess.
  auto fits = [&](const StepSearchResult& r) {
    return r.fitness > out.prior_fitness + kSearchMargin &&
           (!known || r.fitness >= kPriorFitRatio * fit_reference_);
  };
  // With no velocity the search covers every speed and turn rate of the platform, from standing
  // still; with one, what the platform's accelerations allow around the prediction (the motion
  // gate): traffic moving with the sensor can make standing still look right, a car at speed
  // cannot stop in one scan, and along a highway a search beyond the gate finds the guard-rail
  // posts one spacing off.
  const StepSearchResult found = search(known);
  if (!fits(found)) return false;
  prior.predicted = found.T;
  out.reinitialized = motion_.known();
  out.prior_fitness = found.fitness;
  return true;
}

ScanResult Pipeline::process(const PointCloud& cloud) {
  ScanResult out;
  out.index = count_;
  ScopedTimer total(out.times, Module::kTotal);
  const ScanInterval interval = interval_of(cloud, out);
  StepPrior prior;
  prior.interval = interval;
  prior.predicted = motion_.predict(interval.dt);
  prior.gate = motion_.gate(interval.dt);
  // Beyond the sensor's range two scans share nothing: no step is searched farther (a long gap).
  prior.search_range = std::min(config_.motion.max_speed * interval.dt, config_.sensor.max_range);
  prior.yaw_range = std::min(M_PI, config_.motion.max_angular_speed_deg * M_PI / 180.0 * interval.dt);
  const Pose& predicted = prior.predicted;

  // Motion-distortion removal with the constant-velocity prediction (eq. 12), reference = mid-sweep.
  // The prediction is checked first: when it does not bring the scan onto the previous one's
  // surfaces (or there is none yet), the step is searched without it.
  std::vector<Vec3> points, raw;
  std::vector<double> times;
  {
    ScopedTimer t(out.times, Module::kDeskew);
    points = cloud.xyz;
    correct_vertical_angle(points, config_.sensor.vertical_angle_correction_deg);
    if (config_.deskew.enabled && config_.deskew.time_source != TimeSource::kNone)
      times = point_times(cloud, config_.deskew.time_source == TimeSource::kAuto);  // scan 0: at scan 1
    if (!times.empty() || dynamic_) raw = points;
    if (count_ > 0 && !times.empty()) points = deskew(points, times, interval.sweep_motion(predicted));
  }

  SegmentationResult seg;
  {
    ScopedTimer t(out.times, Module::kSegmentation);
    seg = segment(points, config_.sensor, config_.segmentation);
  }

  // The step check: the prediction must bring the scan onto the previous range image about as well
  // as the recent estimates did (the surface of static-looking clusters within kProbeInlier of the
  // previous ranges); when it does not, or there is no velocity yet, the step is searched without
  // it and the scan de-skewed and segmented again with the result.
  std::vector<int> probe;
  if (count_ > 0 && previous_range_.size() == seg.image.range.size()) {
    ScopedTimer t(out.times, Module::kStepCheck);
    probe = probe_pixels(seg, points);
    if (check_prior(prior, seg, points, probe, out) && !times.empty()) {
      points = deskew(raw, times, interval.sweep_motion(predicted));
      seg = segment(points, config_.sensor, config_.segmentation);
      probe = probe_pixels(seg, points);
    }
    // The detection's check of T_coarse: what the recent steps fitted sets the bar.
    prior.previous_range = &previous_range_;
    prior.probe = &probe;
    prior.min_fit = config_.detection.min_registration_fit * fit_reference_;
  }

  // Dynamic-object detection (III.D): T_coarse, re-de-skew, speed matrix, labels, feature mask.
  DynamicOutput dyn;
  if (dynamic_) {
    ScopedTimer t(out.times, Module::kDetection);
    dyn = dynamic_->process(raw, times, std::move(points), seg, prior, cloud.intensity);
    points = std::move(dyn.points);
    out.labels = std::move(dyn.labels);
    out.num_dynamic = dyn.num_dynamic;
    out.pseudo_static = dyn.type2;
    out.coarse_valid = dyn.coarse_valid;
    out.detection_suspended = dyn.suspended;
  }

  FeatureSet features;
  bool redeskewed = false;  // the odometry's motion differed enough from the de-skew's to do it again
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
    // The two-step LM assumes the sensor's z axis is vertical: the ground normal tells.
    const bool level =
        !(seg.ground_plane_valid &&
          seg.ground_normal.normalized().z() < std::cos(config_.odometry.max_level_tilt_deg * M_PI / 180.0));
    // T_coarse (static poles / planes, III.D.1) is the initial guess when valid; the features
    // were de-skewed with it.
    const Pose initial = dynamic_ && dyn.coarse_valid ? dyn.T_coarse : predicted;
    // What unconstrained directions keep: the constant-velocity prediction, or with no velocity
    // yet, the initial guess (the first step's search).
    const Pose motion_prior = motion_.known() ? predicted : initial;
    // How far it can be off: the motion gate (a handheld scanner's turn rate changes too fast
    // for a turn to be held at the last interval's rate, degeneracy.max_prior_error).
    const PriorError prior_error{prior.gate.max_rotation, prior.gate.max_translation};
    // T_coarse passed the motion gate (and is aligned on the range images when refined): an
    // odometry that moves farther than the gate from it has slid along repeated structure (a
    // highway's guard-rail posts, one spacing along) and is not believed. Unless some direction is
    // unconstrained: the odometry kept the constant-velocity prediction there, T_coarse did not.
    const auto believe = [&](auto odometry) {
      if (dynamic_ && dyn.coarse_valid && !odometry.degeneracy.keeps_prior() &&
          !prior.gate.admits(initial.inverse() * odometry.motion))
        odometry.motion = initial;
      return odometry;
    };
    const bool first_pair = first_ && !first_->raw.empty();
    // Scan 1 was de-skewed with T_coarse: so is its target, the first scan. Registering a
    // de-skewed scan to a skewed one is biased by the sweep's motion (a first step up to 6 cm short
    // at 25 km/h, which the map built on the first scan then keeps).
    if (first_pair && dynamic_ && dyn.coarse_valid) deskew_first_scan(interval.sweep_motion(initial));
    auto odo = believe(odometry_.estimate(sharp, initial, reject, level, motion_prior, prior_error));
    if (first_pair) {
      // The first motion is known; de-skew the first scan with it (constant velocity) and
      // estimate again against the corrected target.
      deskew_first_scan(interval.sweep_motion(odo.motion));
      odo = believe(odometry_.estimate(sharp, odo.motion, reject, level, motion_prior, prior_error));
      first_->raw.clear();  // done
    }
    if (!times.empty() && count_ > 0) {
      // The constant-velocity de-skew is wrong where the turn rate changes (start and end of a
      // turn): de-skew the features again with the motion just estimated, and estimate once more
      // when that motion differs much from the prediction. The map and the next scan's target get
      // the refined features.
      const Pose change =
          interval.sweep_motion(initial).pose().inverse() * interval.sweep_motion(odo.motion).pose();
      redeskewed =
          rotation_angle(change) > kRedeskewRotation || translation_norm(change) > kRedeskewTranslation;
      if (redeskewed) {
        const SweepMotion sweep = interval.sweep_motion(odo.motion);
        sharp.edges = deskew(raw, times, features.f_e_index, sweep);
        sharp.planes = deskew(raw, times, features.f_p_index, sweep);
        odo = believe(odometry_.estimate(sharp, odo.motion, reject, level, motion_prior, prior_error));
      }
      const SweepMotion sweep = interval.sweep_motion(odo.motion);
      features.F_e = deskew(raw, times, features.F_e_index, sweep);
      features.F_p = deskew(raw, times, features.F_p_index, sweep);
      // So are the scan's points: the map's, and the image the next step is checked against.
      if (redeskewed) points = deskew(raw, times, sweep);
    }
    if (!probe.empty()) {
      // How well the estimate brings the scan onto the previous one: the reference of the next
      // steps' checks; a step that fits far worse than the recent ones is reported.
      out.fitness = consistency(seg, points, probe, odo.motion, kProbeInlier);
      out.lost = fit_reference_ > 0.0 && out.fitness < kLostFitRatio * fit_reference_;
      if (!out.lost)
        fit_reference_ = fit_reference_ > 0.0 ? 0.8 * fit_reference_ + 0.2 * out.fitness : out.fitness;
    }
    odometry_.set_previous(features.F_e, features.F_p);
    out.rejected_features = odo.rejected;
    odometry_pose_ = normalized(odometry_pose_ * odo.motion);
    out.degeneracy = odo.degeneracy;
    out.degenerate = odo.initialized && odo.degeneracy.degenerate();
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
  // The constant-velocity prediction is the odometry's last motion over the time it took: mapping
  // corrections (and loop closures) move the integrated pose in jumps when they arrive, which are
  // not motion.
  // When the odometry kept the prediction along some direction its step says nothing new there:
  // the velocity is the last step of the scan-to-map registration (scans k-2 -> k-1), which the
  // map constrains where the previous scan did not.
  const std::size_t m = mapped_.size();
  if (count_ > 0 && out.degenerate && out.degeneracy.keeps_prior() && m >= 2 &&
      mapped_[m - 1].first + 1 == count_ && mapped_[m - 2].first + 2 == count_ && previous_dt_ > 0.0) {
    motion_.update(mapped_[m - 2].second.inverse() * mapped_[m - 1].second, previous_dt_);
  } else if (count_ > 0) {
    motion_.update(odometry_poses_[count_ - 1].inverse() * odometry_pose_, interval.dt);
  }
  previous_dt_ = count_ > 0 ? interval.dt : 0.0;
  last_pose_ = out.pose;
  // The next step check compares with this scan's static part: moving objects cannot vouch for a
  // motion (traffic moving with the sensor agrees with standing still).
  if (redeskewed) {
    previous_range_ = reprojected_range(
        seg.image, points, dynamic_ && dyn.checked ? dyn.mask.excluded : std::vector<std::uint8_t>{});
  } else {
    previous_range_ = std::move(seg.image.range);
    if (dynamic_ && dyn.checked)
      for (std::size_t px = 0; px < previous_range_.size(); ++px)
        if (dyn.mask.excluded[px]) previous_range_[px] = 0.0f;
  }
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
  // The odometry's registration of this scan (to the previous one, whose world rotation turns its
  // twists into the map's), unless its step was found not to fit.
  if (count_ > 0 && out.degeneracy.free == 6 && !out.lost)
    in.odometry = second_opinion(out.degeneracy, (correction_ * odometry_poses_[count_ - 1]).linear());
  // A step reported lost is no prediction to keep where the map sees too little.
  if (out.lost) in.prediction_error = {M_PI, config_.sensor.max_range};
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
  if (count_ == 0) {              // wait for the first motion (scan 1) to de-skew it
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

void Pipeline::deskew_first_scan(const SweepMotion& sweep_motion) {
  FirstScan& f = *first_;
  f.input.features.edges = deskew(f.raw, f.times, f.F_e_index, sweep_motion);
  f.input.features.planes = deskew(f.raw, f.times, f.F_p_index, sweep_motion);
  const std::vector<Vec3> points = deskew(f.raw, f.times, sweep_motion);
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
      o.result =
          mapper_.process(in.scan, in.features, in.predicted, in.keyframe, in.odometry, in.prediction_error);
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
    out->map_degeneracy = o.result.registration.degeneracy;
    out->times[Module::kMapping] += o.ms;
  }
}

void Pipeline::finish() {
  if (first_) {  // a single scan: mapped as it is
    start_job(std::move(first_->input));
    first_.reset();
  }
  integrate_job(nullptr);
  mapper_.finish();  // a loop closure still running
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
