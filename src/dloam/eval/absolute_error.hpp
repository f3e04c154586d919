// Absolute trajectory error (ATE) and per-frame relative pose error (RPE).
// ATE: RMSE of the position differences, either with the poses as given (KITTI files both start
// at the identity, so this is the error after anchoring the first pose) or after the closed-form
// least-squares SE(3) alignment of the estimated positions onto the ground truth (Umeyama 1991 /
// Horn 1987, no scale). RPE: for consecutive frames, E_i = (G_i^-1 G_i+1)^-1 (P_i^-1 P_i+1).
#pragma once

#include <cstddef>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::eval {

struct ErrorStats {
  std::size_t count = 0;
  double mean = 0.0;
  double rmse = 0.0;
  double max = 0.0;
};

/// Mean, RMSE and max of a list of non-negative errors (all zero when empty).
ErrorStats error_stats(const std::vector<double>& errors);

/// ATE of the positions as given [m]. Throws InputError if the sizes differ or are empty.
ErrorStats ate(const std::vector<Pose>& gt, const std::vector<Pose>& est);

/// Rigid transform T minimising sum |g_i - T p_i|^2 over positions (Eigen::umeyama, no scale).
Pose align_positions(const std::vector<Pose>& gt, const std::vector<Pose>& est);

/// ATE after applying align_positions(gt, est) to the estimate [m].
ErrorStats ate_aligned(const std::vector<Pose>& gt, const std::vector<Pose>& est);

/// A frame-to-frame step is tracked when its error is within these bounds.
constexpr double kTrackedStepM = 0.05;
constexpr double kTrackedStepDeg = 1.0;

struct Rpe {
  ErrorStats trans_m;
  ErrorStats rot_deg;
  std::size_t steps = 0;    ///< frame-to-frame steps
  std::size_t tracked = 0;  ///< steps within kTrackedStepM and kTrackedStepDeg
};

/// Per-frame RPE between consecutive frames (frames - 1 pairs).
Rpe rpe(const std::vector<Pose>& gt, const std::vector<Pose>& est);

}  // namespace dloam::eval
