#include "dloam/core/mapping.hpp"

#include <cmath>
#include <utility>

#include "dloam/core/se3.hpp"
#include "dloam/core/voxel_grid.hpp"

namespace dloam {

double edge_line_ratio_for(double configured, int rows, bool car) {
  if (configured > 0.0) return configured;
  return car && rows >= 64 ? 10.0 : kLoamLineRatio;
}

LoopParams loop_params(const MappingConfig& config, double scan_rate_hz) {
  LoopParams p;
  p.search_radius = config.loop_search_radius;
  p.min_time_s = config.loop_min_time_s;
  p.scan_rate_hz = scan_rate_hz;
  p.max_fitness = config.loop_max_fitness;
  p.edge_leaf = config.edge_leaf_size;
  p.plane_leaf = config.plane_leaf_size;
  return p;
}

bool Mapper::needs_keyframe(const Pose& pose) const {
  if (local_.empty()) return true;
  const Pose rel = local_.keyframes().back().pose.inverse() * pose;
  return rel.translation().norm() >= config_.keyframe_distance ||
         rotation_angle(rel) >= config_.keyframe_angle_deg * M_PI / 180.0;
}

MappingResult Mapper::process(std::size_t scan, const FeatureSource& features, const Pose& predicted,
                              std::optional<bool> keyframe, const std::optional<SecondOpinion>& odometry,
                              const PriorError& prediction_error) {
  MappingResult out;
  last_scan_ = scan;
  take_loop(scan, false, &out);
  // A loop taken since the odometry's prediction was made moved the map: so does the prediction.
  out.pose = normalized(shift_ * predicted);
  shift_ = Pose::Identity();
  // The scan's features at the map's resolution: the source of registration and of a keyframe.
  const FeatureSource source{voxel_downsample_points(features.edges, config_.edge_leaf_size),
                             voxel_downsample_points(features.planes, config_.plane_leaf_size),
                             {},
                             {}};
  if (!local_.empty()) {
    RegistrationParams p;
    p.max_iterations = config_.max_iterations;
    p.min_line_ratio = config_.edge_line_ratio > 0.0 ? config_.edge_line_ratio : kLoamLineRatio;
    p.max_correspondence = 1.0;
    p.dof = kAllDof;
    p.degeneracy = degeneracy_;
    p.prior = out.pose;  // the odometry's motion along directions the map does not constrain
    p.prior_error = prediction_error;
    p.second_opinion = odometry;
    out.registration = register_features(source, local_.around(out.pose.translation()), out.pose, p);
    out.pose = out.registration.T;
  }
  if (keyframe.value_or(needs_keyframe(out.pose))) {
    local_.add({scan, out.pose, source.edges, source.planes});
    out.keyframe = true;
    anchors_.push_back({scan, local_.keyframes().size() - 1, out.pose});
    start_loop(scan);
    if (pending_ && pending_->due_scan <= scan) {  // no latency: the loop is taken on this scan
      take_loop(scan, true, &out);
      out.pose = normalized(shift_ * out.pose);
      shift_ = Pose::Identity();
    }
  }
  return out;
}

namespace {
// Odometry and loop uncertainties: the loop is as certain as one odometry step, so an accepted loop
// spreads the drift along the whole chain; the Huber width only bounds gross outliers.
constexpr double kSigmaRotation = 0.01, kSigmaTranslation = 0.1;  // rad, m

PoseGraphEdge loop_edge(const LoopConstraint& loop) {
  return {loop.candidate, loop.current, loop.relative,
          information_from_sigmas(kSigmaRotation, kSigmaTranslation), true};
}
}  // namespace

void Mapper::start_loop(std::size_t scan) {
  const std::size_t k = local_.keyframes().size() - 1;
  const std::vector<Keyframe>& kfs = local_.keyframes();
  if (k > 0)
    edges_.push_back({k - 1, k, normalized(kfs[k - 1].pose.inverse() * kfs[k].pose),
                      information_from_sigmas(kSigmaRotation, kSigmaTranslation), false});
  if (!config_.loop_closure || pending_ || scan < no_loop_before_) return;
  const auto candidate = find_loop_candidate(kfs, k, loop_params_);
  if (!candidate) return;

  // The job's own copy of what verify_loop reads: every keyframe's scan and pose, the features of
  // the candidate's submap and of keyframe k (the keyframes go on growing beside it).
  std::vector<Keyframe> view(kfs.size());
  const auto [lo, hi] = loop_submap(*candidate, kfs.size(), loop_params_);
  for (std::size_t i = 0; i < kfs.size(); ++i) {
    view[i].scan = kfs[i].scan;
    view[i].pose = kfs[i].pose;
    if (i == k || (i >= lo && i <= hi)) {
      view[i].edges = kfs[i].edges;
      view[i].planes = kfs[i].planes;
    }
  }
  PendingLoop p;
  p.due_scan = scan + static_cast<std::size_t>(std::ceil(config_.loop_latency_s * loop_params_.scan_rate_hz));
  p.keyframe = k;
  p.pose_at_start = kfs[k].pose;
  p.map = std::make_unique<const GlobalMap::Snapshot>(global_.snapshot());
  const auto job = [view = std::move(view), edges = edges_, k, c = *candidate, params = loop_params_,
                    map = p.map.get(), leaf = config_.map_leaf_size]() mutable {
    LoopOutcome o;
    o.loop = verify_loop(view, k, c, params);
    if (!o.loop) return o;
    edges.push_back(loop_edge(*o.loop));
    std::vector<Pose> poses;
    poses.reserve(view.size());
    for (const Keyframe& kf : view) poses.push_back(kf.pose);
    PoseGraphOptions options;
    options.loop_huber = 3.0;
    o.poses = optimize_pose_graph(poses, edges, options);
    o.occupancy = GlobalMap::rebuild(*map, o.poses, leaf);
    return o;
  };
  // No latency: run on this thread when taken, at once.
  p.outcome = std::async(p.due_scan <= scan ? std::launch::deferred : std::launch::async, job);
  pending_ = std::move(p);
}

void Mapper::take_loop(std::size_t scan, bool force, MappingResult* out) {
  if (!pending_ || (!force && scan < pending_->due_scan)) return;
  PendingLoop taken = std::move(*pending_);  // no longer pending, also when the job threw
  pending_.reset();
  LoopOutcome o = taken.outcome.get();  // rethrows the job's exception
  if (!o.loop) return;
  const std::size_t k = taken.keyframe;
  const Pose& pose_at_start = taken.pose_at_start;
  // Keyframes 0..k as optimised; the ones made since move rigidly with keyframe k.
  const std::vector<Keyframe>& kfs = local_.keyframes();
  std::vector<Pose> poses = std::move(o.poses);
  const Pose shift = normalized(poses[k] * pose_at_start.inverse());
  for (std::size_t i = poses.size(); i < kfs.size(); ++i) poses.push_back(normalized(shift * kfs[i].pose));
  edges_.push_back(loop_edge(*o.loop));
  local_.set_poses(poses);
  global_.adopt(std::move(o.occupancy), poses);
  loops_.push_back(*o.loop);
  anchors_.push_back({scan, kfs.size() - 1, poses.back()});
  shift_ = normalized(shift * shift_);
  no_loop_before_ =
      scan + static_cast<std::size_t>(std::ceil(config_.loop_min_interval_s * loop_params_.scan_rate_hz));
  if (out) out->loop = o.loop;
}

void Mapper::finish() { take_loop(last_scan_ + 1, true, nullptr); }

std::vector<Pose> Mapper::corrected_trajectory(const std::vector<Pose>& scan_poses) const {
  std::vector<Pose> out = scan_poses;
  const std::vector<Keyframe>& kfs = local_.keyframes();
  std::size_t a = 0;  // the next anchor not yet governing
  Pose delta = Pose::Identity();
  bool governed = false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    while (a < anchors_.size() && anchors_[a].scan <= i) {
      delta = kfs[anchors_[a].keyframe].pose * anchors_[a].reported.inverse();
      governed = true;
      ++a;
    }
    if (governed) out[i] = normalized(delta * scan_poses[i]);
  }
  return out;
}

void Mapper::add_to_global_map(const std::vector<Vec3>& points) {
  if (local_.empty()) return;
  global_.add(local_.keyframes().size() - 1, points, local_.keyframes().back().pose);
}

void Mapper::add_to_global_map(const std::vector<Vec3>& points, const Pose& pose) {
  if (local_.empty()) return;
  const Pose& keyframe = local_.keyframes().back().pose;
  const Pose to_keyframe = keyframe.inverse() * pose;
  std::vector<Vec3> in_keyframe;
  in_keyframe.reserve(points.size());
  for (const Vec3& p : points) in_keyframe.push_back(to_keyframe * p);
  global_.add(local_.keyframes().size() - 1, in_keyframe, keyframe);
}

std::vector<Vec3> Mapper::global_map() const {
  std::vector<Pose> poses;
  poses.reserve(local_.keyframes().size());
  for (const Keyframe& kf : local_.keyframes()) poses.push_back(kf.pose);
  return global_.points(poses);
}

}  // namespace dloam
