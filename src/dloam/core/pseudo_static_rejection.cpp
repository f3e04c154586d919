#include "dloam/core/pseudo_static_rejection.hpp"

#include <algorithm>
#include <cmath>

namespace dloam {

RejectionResult reject_pseudo_static(const FeatureSource& source, const Pose& initial, int N_pseudo,
                                     double beta, double inlier_distance, const PoseEstimator& estimate) {
  FeatureSource src = with_unit_weights(source);
  const std::size_t n = src.edges.size() + src.planes.size();
  auto weight = [&](std::size_t i) -> double& { return feature_weight(src, i); };

  RejectionResult out;
  out.kept.assign(n, 1);
  Pose T = initial;
  for (int round = 0; round < std::max(1, N_pseudo); ++round) {
    out.result = estimate(src, T);
    ++out.rounds;
    T = out.result.T;
    const auto& res = out.result.residuals;
    std::vector<std::size_t> matched;
    std::size_t active = 0, outliers = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!out.kept[i] || weight(i) <= 0.0) continue;
      ++active;
      if (i < res.size() && res[i] >= 0.0) {
        matched.push_back(i);
        if (res[i] > inlier_distance) ++outliers;
      }
    }
    const auto quota = static_cast<std::size_t>(std::floor(beta * static_cast<double>(active)));
    if (round + 1 >= N_pseudo || quota == 0 || outliers < quota) break;
    // Remove the beta fraction with the largest matching error.
    std::stable_sort(matched.begin(), matched.end(),
                     [&](std::size_t a, std::size_t b) { return res[a] > res[b]; });
    for (std::size_t k = 0; k < quota && k < matched.size(); ++k) {
      out.kept[matched[k]] = 0;
      weight(matched[k]) = 0.0;
      ++out.removed;
    }
  }
  return out;
}

}  // namespace dloam
