// Runs every odometry metric on one pair of trajectories.
#include "dloam/eval/odometry_metrics.hpp"

#include <string>

namespace dloam::eval {

OdometryResult evaluate_odometry(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const SegmentOptions& options) {
  if (gt.size() != est.size()) {
    throw InputError("odometry evaluation: ground truth has " + std::to_string(gt.size()) +
                     " poses but the estimate has " + std::to_string(est.size()));
  }
  if (gt.empty()) throw InputError("odometry evaluation: the trajectories are empty");
  OdometryResult result;
  result.frames = gt.size();
  result.path_length_m = trajectory_distances(gt).back();
  result.relative = relative_error(gt, est, options);
  result.ate = ate(gt, est);
  result.alignment = align_positions(gt, est);
  result.ate_aligned = ate_aligned(gt, est);
  result.rpe = rpe(gt, est);
  return result;
}

}  // namespace dloam::eval
