#include "dloam/core/mapping.hpp"

#include <cmath>
#include <utility>

#include "dloam/core/se3.hpp"
#include "dloam/core/voxel_grid.hpp"

namespace dloam {

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
                              std::optional<bool> keyframe) {
  MappingResult out;
  out.pose = predicted;
  // The scan's features at the map's resolution: the source of registration and of a keyframe.
  const FeatureSource source{voxel_downsample_points(features.edges, config_.edge_leaf_size),
                             voxel_downsample_points(features.planes, config_.plane_leaf_size),
                             {},
                             {}};
  if (!local_.empty()) {
    RegistrationParams p;
    p.max_iterations = config_.max_iterations;
    p.max_correspondence = 1.0;
    p.dof = kAllDof;
    p.degeneracy = degeneracy_;
    p.prior = predicted;  // the odometry's motion along directions the map does not constrain
    out.registration = register_features(source, local_.around(predicted.translation()), predicted, p);
    out.pose = out.registration.T;
  }
  if (keyframe.value_or(needs_keyframe(out.pose))) {
    local_.add({scan, out.pose, source.edges, source.planes});
    out.keyframe = true;
    close_loop(out);
    reported_.push_back(out.pose);
  }
  return out;
}

void Mapper::close_loop(MappingResult& out) {
  // Odometry and loop uncertainties: the loop is as certain as one odometry step, so an accepted loop
  // spreads the drift along the whole chain; the Huber width only bounds gross outliers.
  constexpr double kSigmaRotation = 0.01, kSigmaTranslation = 0.1;  // rad, m
  const std::size_t k = local_.keyframes().size() - 1;
  const std::vector<Keyframe>& kfs = local_.keyframes();
  if (k > 0)
    edges_.push_back({k - 1, k, normalized(kfs[k - 1].pose.inverse() * kfs[k].pose),
                      information_from_sigmas(kSigmaRotation, kSigmaTranslation), false});
  if (!config_.loop_closure) return;
  const auto loop = detect_loop(kfs, k, loop_params_);
  if (!loop) return;
  edges_.push_back({loop->candidate, loop->current, loop->relative,
                    information_from_sigmas(kSigmaRotation, kSigmaTranslation), true});
  std::vector<Pose> poses;
  poses.reserve(kfs.size());
  for (const Keyframe& kf : kfs) poses.push_back(kf.pose);
  PoseGraphOptions options;
  options.loop_huber = 3.0;
  const std::vector<Pose> optimized = optimize_pose_graph(poses, edges_, options);
  local_.set_poses(optimized);
  global_.move(optimized);
  out.pose = optimized[k];
  out.loop = loop;
  loops_.push_back(*loop);
}

std::vector<Pose> Mapper::corrected_trajectory(const std::vector<Pose>& scan_poses) const {
  std::vector<Pose> out = scan_poses;
  const std::vector<Keyframe>& kfs = local_.keyframes();
  std::size_t k = 0;  // the next keyframe not yet governing
  Pose delta = Pose::Identity();
  bool governed = false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    while (k < kfs.size() && kfs[k].scan <= i) {
      delta = kfs[k].pose * reported_[k].inverse();
      governed = true;
      ++k;
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
