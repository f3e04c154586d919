// Loop-closure detection (LeGO-LOAM, paper III.G): the nearest earlier keyframe within a search
// radius that is old enough is the candidate; the current keyframe's features are registered
// (point-to-line / point-to-plane, coarse to fine) against a world-frame submap of the candidate and
// its neighbouring keyframes, and the loop is accepted when the mean residual is small and enough
// features matched. The result is a relative-pose constraint for the pose graph.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "dloam/core/local_map.hpp"

namespace dloam {

struct LoopParams {
  double search_radius = 7.0;    ///< m between the current keyframe and a candidate
  double min_time_s = 30.0;      ///< a candidate's scan is at least this much older
  double scan_rate_hz = 10.0;    ///< converts min_time_s to scans
  double max_fitness = 0.3;      ///< m: accept when the mean registration residual is below
  int submap_neighbours = 12;    ///< the submap holds the candidate and +-this many keyframes
  int min_matches = 100;         ///< ... and at least this many matched features
  double min_match_ratio = 0.6;  ///< ... and at least this fraction of the current features
  int max_iterations = 20;       ///< registration iterations per coarse-to-fine stage
  double edge_leaf = 0.2;        ///< submap voxel sizes
  double plane_leaf = 0.4;
};

/// Accepted loop: Z = T_candidate^-1 T_current, with T_current the pose registered to the submap.
struct LoopConstraint {
  std::size_t candidate = 0;  ///< keyframe indices
  std::size_t current = 0;
  Pose relative = Pose::Identity();
  Pose current_pose = Pose::Identity();  ///< registered world pose of the current keyframe
  double fitness = 0.0;                  ///< mean residual (m)
  int matches = 0;
};

/// Nearest keyframe before `current` within the radius and at least min_time_s older, if any.
std::optional<std::size_t> find_loop_candidate(const std::vector<Keyframe>& keyframes, std::size_t current,
                                               const LoopParams& params);

/// The first and last keyframe of the submap around `candidate` among `keyframes` (> candidate).
std::pair<std::size_t, std::size_t> loop_submap(std::size_t candidate, std::size_t keyframes,
                                                const LoopParams& params);

/// Registers keyframe `current` against the submap around `candidate`; the constraint if accepted.
std::optional<LoopConstraint> verify_loop(const std::vector<Keyframe>& keyframes, std::size_t current,
                                          std::size_t candidate, const LoopParams& params);

/// Candidate search then verification.
std::optional<LoopConstraint> detect_loop(const std::vector<Keyframe>& keyframes, std::size_t current,
                                          const LoopParams& params);

}  // namespace dloam
