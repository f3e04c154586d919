// Loop candidate search and geometric verification by feature registration against a submap.
#include "dloam/core/loop_closure.hpp"

#include <algorithm>

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {

/// Scans between two keyframes (0 when `later` is not later).
double scans_between(const Keyframe& earlier, const Keyframe& later) {
  return later.scan > earlier.scan ? static_cast<double>(later.scan - earlier.scan) : 0.0;
}

bool old_enough(const Keyframe& kf, const Keyframe& current, const LoopParams& params) {
  return scans_between(kf, current) >= params.min_time_s * params.scan_rate_hz;
}

}  // namespace

std::optional<std::size_t> find_loop_candidate(const std::vector<Keyframe>& keyframes, std::size_t current,
                                               const LoopParams& params) {
  if (current >= keyframes.size()) return std::nullopt;
  const Keyframe& cur = keyframes[current];
  std::optional<std::size_t> best;
  double best_distance = params.search_radius;
  for (std::size_t i = 0; i < current; ++i) {
    if (!old_enough(keyframes[i], cur, params)) continue;
    const double d = (keyframes[i].pose.translation() - cur.pose.translation()).norm();
    if (d < best_distance) {  // strict: the earliest of equally near keyframes wins
      best_distance = d;
      best = i;
    }
  }
  return best;
}

std::pair<std::size_t, std::size_t> loop_submap(std::size_t candidate, std::size_t keyframes,
                                                const LoopParams& params) {
  const auto reach = static_cast<std::size_t>(std::max(0, params.submap_neighbours));
  return {candidate >= reach ? candidate - reach : 0, std::min(keyframes - 1, candidate + reach)};
}

std::optional<LoopConstraint> verify_loop(const std::vector<Keyframe>& keyframes, std::size_t current,
                                          std::size_t candidate, const LoopParams& params) {
  if (current >= keyframes.size() || candidate >= current) return std::nullopt;
  const Keyframe& cur = keyframes[current];
  // World-frame submap: the candidate and its neighbours, none of them recent relative to `current`.
  const auto [lo, hi] = loop_submap(candidate, keyframes.size(), params);
  std::vector<Vec3> edges, planes;
  for (std::size_t i = lo; i <= hi; ++i) {
    const Keyframe& kf = keyframes[i];
    if (i == current || !old_enough(kf, cur, params)) continue;
    for (const Vec3& p : kf.edges) edges.push_back(kf.pose * p);
    for (const Vec3& p : kf.planes) planes.push_back(kf.pose * p);
  }
  FeatureMap submap;
  submap.edges.build(voxel_downsample_points(edges, params.edge_leaf));
  submap.planes.build(voxel_downsample_points(planes, params.plane_leaf));

  // Coarse to fine: the drift to undo can be metres, the final gate is the mapping's 1 m.
  const FeatureSource source{cur.edges, cur.planes, {}, {}};
  RegistrationParams rp;
  rp.max_iterations = params.max_iterations;
  rp.dof = kAllDof;
  // No prior to keep here: the loop is refused only for a direction with almost nothing on it
  // (min_features), not for one that a small share of the matches holds.
  rp.degeneracy.min_fraction = 0.0;
  RegistrationResult r;
  r.T = cur.pose;
  for (double gate : {4.0, 2.0, 1.0}) {
    rp.max_correspondence = gate;
    r = register_features(source, submap, r.T, rp);
  }
  const int matches = r.edge_matches + r.plane_matches;
  const auto features = static_cast<double>(cur.edges.size() + cur.planes.size());
  if (r.degenerate() || matches < params.min_matches || matches < params.min_match_ratio * features ||
      !(r.mean_residual < params.max_fitness))
    return std::nullopt;

  LoopConstraint c;
  c.candidate = candidate;
  c.current = current;
  c.current_pose = normalized(r.T);
  c.relative = normalized(keyframes[candidate].pose.inverse() * c.current_pose);
  c.fitness = r.mean_residual;
  c.matches = matches;
  return c;
}

std::optional<LoopConstraint> detect_loop(const std::vector<Keyframe>& keyframes, std::size_t current,
                                          const LoopParams& params) {
  const auto candidate = find_loop_candidate(keyframes, current, params);
  if (!candidate) return std::nullopt;
  return verify_loop(keyframes, current, *candidate, params);
}

}  // namespace dloam
