// RANSAC-style rejection of pseudo-static features in the odometry (paper III.F): up to N_pseudo
// rounds; each estimates the pose from the remaining features, counts the outliers (residual
// above an inlier distance) and removes the beta fraction of the remaining features that match
// worst. It stops early when fewer than beta of the features are outliers, so a scene without
// pseudo-static objects costs one estimate and keeps every feature.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "dloam/core/registration.hpp"

namespace dloam {

/// Estimates a pose from the weighted features (weight 0 = removed), starting from `initial`;
/// the result's `residuals` are per feature, edges then planes (-1 unmatched).
using PoseEstimator = std::function<RegistrationResult(const FeatureSource&, const Pose& initial)>;

struct RejectionResult {
  RegistrationResult result;       ///< the last estimate
  int rounds = 0;                  ///< estimates made
  std::size_t removed = 0;         ///< features removed
  std::vector<std::uint8_t> kept;  ///< per feature (edges then planes)
};

RejectionResult reject_pseudo_static(const FeatureSource& source, const Pose& initial, int N_pseudo,
                                     double beta, double inlier_distance, const PoseEstimator& estimate);

}  // namespace dloam
