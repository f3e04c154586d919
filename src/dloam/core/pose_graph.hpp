// Pose graph of keyframe poses (LeGO-LOAM's loop-closure back end, paper III.G): nodes are world
// poses, edges are relative-pose measurements Z_ij = T_i^-1 T_j (odometry between consecutive
// keyframes, loop constraints) with 6x6 information matrices. Optimised with Ceres (autodiff,
// quaternion manifold), first pose fixed, robust (Huber) loss on loop edges; single-threaded and
// in a fixed order, so the result is deterministic.
#pragma once

#include <vector>

#include "dloam/core/se3.hpp"

namespace dloam {

/// A relative-pose constraint Z = T_from^-1 T_to. Error order [rotation; translation] (twist order),
/// rotation error = 2 vec(q_Z^-1 q_from^-1 q_to), translation error = R_Z^T (R_from^T (t_to - t_from) - t_Z).
struct PoseGraphEdge {
  std::size_t from = 0;
  std::size_t to = 0;
  Pose measurement = Pose::Identity();
  Mat6 information = Mat6::Identity();
  bool loop = false;  ///< loop edges get the robust loss
};

/// Diagonal information from standard deviations (rad, m).
Mat6 information_from_sigmas(double sigma_rotation, double sigma_translation);

struct PoseGraphOptions {
  int max_iterations = 100;
  double loop_huber = 1.0;  ///< Huber width on the whitened loop residual (in standard deviations)
};

struct PoseGraphSummary {
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
  bool usable = false;  ///< Ceres returned a usable solution
};

/// Optimises `poses` (node i = poses[i]) under `edges`; poses[0] stays fixed. Returns the new poses
/// (the input ones when the solve fails). Throws std::invalid_argument on an edge to a missing node.
std::vector<Pose> optimize_pose_graph(const std::vector<Pose>& poses, const std::vector<PoseGraphEdge>& edges,
                                      const PoseGraphOptions& options = {},
                                      PoseGraphSummary* summary = nullptr);

}  // namespace dloam
