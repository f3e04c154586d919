// Odometry evaluation in one call: KITTI devkit relative error (relative_error.hpp), ATE with and
// without SE(3) alignment and per-frame RPE (absolute_error.hpp). Poses are compared in the frame
// they are given in; the caller converts both trajectories to the LiDAR frame (Tr^-1 P Tr) first
// when a KITTI calibration is known, as `dloam eval odometry --calib` does.
#pragma once

#include <cstddef>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/eval/absolute_error.hpp"
#include "dloam/eval/relative_error.hpp"

namespace dloam::eval {

struct OdometryResult {
  std::size_t frames = 0;
  double path_length_m = 0.0;  ///< ground-truth path length
  RelativeError relative;
  ErrorStats ate;          ///< positions as given [m]
  ErrorStats ate_aligned;  ///< after SE(3) alignment [m]
  Pose alignment = Pose::Identity();
  Rpe rpe;
};

/// Throws InputError if the trajectories are empty or of different lengths.
OdometryResult evaluate_odometry(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const SegmentOptions& options = {});

}  // namespace dloam::eval
