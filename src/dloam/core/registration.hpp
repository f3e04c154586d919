// Feature registration by Levenberg-Marquardt / Gauss-Newton: point-to-line residuals for edge
// features and point-to-plane residuals for plane features (LOAM / LeGO-LOAM, paper III.F-G),
// with a subset of the six degrees of freedom free (the two-step LM of the odometry),
// per-feature weights (distance weights and eq. 15 compensation), a robust kernel, and solution
// remapping (degeneracy.hpp): along directions the geometry does not constrain, the estimate keeps
// the motion prior instead of the update.
#pragma once

#include <optional>
#include <vector>

#include "dloam/core/degeneracy.hpp"
#include "dloam/core/kdtree.hpp"
#include "dloam/core/se3.hpp"

namespace dloam {

/// Target features in one frame, with their search trees.
struct FeatureMap {
  KdTree edges;
  KdTree planes;
};

/// Source features (in the source frame) with optional per-feature weights (empty = 1).
struct FeatureSource {
  std::vector<Vec3> edges;
  std::vector<Vec3> planes;
  std::vector<double> edge_weights;
  std::vector<double> plane_weights;
};

/// `src` with every empty weight vector filled with 1, so features can be switched off one by one.
FeatureSource with_unit_weights(FeatureSource src);
/// The weight of feature i of a source from with_unit_weights (edges first, then planes).
inline double& feature_weight(FeatureSource& src, std::size_t i) {
  return i < src.edges.size() ? src.edge_weights[i] : src.plane_weights[i - src.edges.size()];
}

/// LOAM's test of a line: the largest eigenvalue at least 3 times the second.
inline constexpr double kLoamLineRatio = 3.0;

struct RegistrationParams {
  int max_iterations = 20;
  double max_correspondence = 1.0;  ///< m: neighbours farther than this give no residual
  int neighbours = 5;
  /// An edge's neighbours form a line when the variance along it is at least this many times the
  /// largest variance across it (eigenvalues of their covariance).
  double min_line_ratio = kLoamLineRatio;
  double huber = 0.1;  ///< m: robust kernel width
  /// Which directions count as unconstrained. They are found at the initial guess (first
  /// iteration) and stay fixed: the iterations then minimise over the constrained directions only.
  DegeneracyConfig degeneracy;
  /// The motion prior: along unconstrained directions the estimate takes its value (solution
  /// remapping). None: the initial guess's.
  std::optional<Pose> prior;
  /// How far the prior can be off: only directions where that is within degeneracy.max_prior_error
  /// keep it (Degeneracy::held); zero: all unconstrained ones do.
  PriorError prior_error;
  /// Another registration of the same motion, asked about translations the share test alone leaves
  /// unconstrained (analyse_degeneracy).
  std::optional<SecondOpinion> second_opinion;
  double convergence_rotation = 1e-5;     ///< rad
  double convergence_translation = 1e-4;  ///< m
  /// Nearest neighbours are searched again when the pose moved more than this since the last search.
  double reassociate_translation = 0.01;  ///< m
  double reassociate_rotation = 0.001;    ///< rad
  DofMask dof = kAllDof;
};

struct RegistrationResult {
  Pose T = Pose::Identity();  ///< source -> target
  int iterations = 0;
  int edge_matches = 0;
  int plane_matches = 0;
  double mean_residual = 0.0;  ///< m, over matched features at the last iteration
  /// Some free direction the geometry does not constrain (kept from the prior), or fewer than 10
  /// matches (the initial guess stands).
  [[nodiscard]] bool degenerate() const { return degeneracy.degenerate(); }
  Degeneracy degeneracy;  ///< of the free directions, at the first iteration
  /// J^T W J over all six degrees of freedom at the last iteration (twist coordinates about the
  /// sensor position, rad and m): registrations of different features of one scan add up.
  Mat6 normal_matrix = Mat6::Zero();
  /// Per-feature absolute residual of the last iteration (-1 when unmatched), edges then planes.
  std::vector<double> residuals;
};

/// A `params.dof` with no free direction only evaluates: the residuals at `initial`.
RegistrationResult register_features(const FeatureSource& src, const FeatureMap& target, const Pose& initial,
                                     const RegistrationParams& params);

}  // namespace dloam
