#include "dloam/core/odometry.hpp"

namespace dloam {

OdometryResult ScanToScanOdometry::process(const FeatureSource& sharp, std::vector<Vec3> all_edges,
                                           std::vector<Vec3> all_planes, const Pose& predicted) {
  OdometryResult out;
  out.motion = predicted;
  if (previous_) {
    out.initialized = true;
    RegistrationParams p;
    p.max_iterations = config_.max_iterations;
    p.max_correspondence = config_.max_correspondence;

    FeatureSource planes_only{{}, sharp.planes, {}, sharp.plane_weights};
    p.dof = kPlaneStepDof;
    out.plane_step = register_features(planes_only, *previous_, out.motion, p);

    FeatureSource edges_only{sharp.edges, {}, sharp.edge_weights, {}};
    p.dof = kEdgeStepDof;
    out.edge_step = register_features(edges_only, *previous_, out.plane_step.T, p);
    out.motion = out.edge_step.T;
  }
  previous_ = std::make_unique<FeatureMap>();
  previous_->edges.build(std::move(all_edges));
  previous_->planes.build(std::move(all_planes));
  return out;
}

}  // namespace dloam
