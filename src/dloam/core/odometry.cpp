#include "dloam/core/odometry.hpp"

#include "dloam/core/pseudo_static_rejection.hpp"

namespace dloam {

OdometryResult ScanToScanOdometry::estimate(const FeatureSource& sharp, const Pose& predicted,
                                            bool with_rejection, bool level, const std::optional<Pose>& prior,
                                            const PriorError& prior_error) const {
  OdometryResult out;
  out.motion = predicted;
  if (previous_) {
    out.initialized = true;
    RegistrationParams p;
    p.max_iterations = config_.max_iterations;
    p.min_line_ratio = config_.edge_line_ratio;
    p.max_correspondence = config_.max_correspondence;
    if (prior) {  // directions the features do not constrain keep the prior (solution remapping)
      p.degeneracy = degeneracy_;
      p.prior = *prior;
      p.prior_error = prior_error;
    } else {  // no prior to keep: every direction is estimated; the degeneracy is only reported
      p.degeneracy.min_features = 0.0;
      p.degeneracy.min_fraction = 0.0;
      p.degeneracy.rotation_radius = degeneracy_.rotation_radius;
    }

    auto two_step = [&](const FeatureSource& src, const Pose& initial) {
      if (!level) {
        // A tilted sensor: its z axis is not the world's vertical, so planes do not constrain
        // [t_z, roll, pitch] alone: every feature constrains all six degrees of freedom at once.
        p.dof = kAllDof;
        out.plane_step = out.edge_step = register_features(src, *previous_, initial, p);
        return out.edge_step;
      }
      FeatureSource planes_only{{}, src.planes, {}, src.plane_weights};
      p.dof = kPlaneStepDof;
      out.plane_step = register_features(planes_only, *previous_, initial, p);

      FeatureSource edges_only{src.edges, {}, src.edge_weights, {}};
      p.dof = kEdgeStepDof;
      out.edge_step = register_features(edges_only, *previous_, out.plane_step.T, p);
      // Residuals of the combined estimate, edges then planes (for the rejection).
      RegistrationResult r = out.edge_step;
      r.residuals.insert(r.residuals.end(), out.plane_step.residuals.begin(), out.plane_step.residuals.end());
      return r;
    };
    if (with_rejection && config_.pseudo_static_rejection) {
      const auto rej = reject_pseudo_static(sharp, out.motion, config_.N_pseudo, config_.beta,
                                            config_.pseudo_inlier_distance, two_step);
      out.rejection_rounds = rej.rounds;
      out.rejected = rej.removed;
    } else {
      two_step(sharp, out.motion);
    }
    out.motion = out.edge_step.T;
    const Mat6 H = level ? Mat6(out.plane_step.normal_matrix + out.edge_step.normal_matrix)
                         : out.edge_step.normal_matrix;
    int matches = out.edge_step.edge_matches + out.edge_step.plane_matches;
    if (level) matches += out.plane_step.edge_matches + out.plane_step.plane_matches;
    out.degeneracy = analyse_degeneracy(H, matches, kAllDof, degeneracy_, prior_error);
    if (!prior) out.degeneracy.held = 0;  // reported only: nothing kept a prior
  }
  return out;
}

void ScanToScanOdometry::set_previous(std::vector<Vec3> all_edges, std::vector<Vec3> all_planes) {
  previous_ = std::make_unique<FeatureMap>();
  previous_->edges.build(std::move(all_edges));
  previous_->planes.build(std::move(all_planes));
}

}  // namespace dloam
