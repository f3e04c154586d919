#include "dloam/core/step_search.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "dloam/core/preregistration.hpp"
#include "dloam/core/se3.hpp"

namespace dloam {

namespace {
RegistrationParams stage_params(double radius, int iterations) {
  RegistrationParams p;
  p.max_iterations = iterations;
  p.max_correspondence = radius;
  p.huber = std::max(0.1, 0.3 * radius);
  p.dof = kAllDof;
  return p;
}

/// Offsets k * step for k = -n..n with n * step <= max (0 first, then alternating sides).
std::vector<double> offsets(double max, double step) {
  std::vector<double> out{0.0};
  if (step <= 0.0) return out;
  const int n = static_cast<int>(std::floor(max / step + 1e-9));
  for (int k = 1; k <= n; ++k) {
    out.push_back(k * step);
    out.push_back(-k * step);
  }
  return out;
}
}  // namespace

StepSearchResult search_step(const FeatureSource& source, const FeatureMap& target,
                             const std::vector<Pose>& centres, const StepSearchOptions& requested,
                             const StepScore& score) {
  StepSearchOptions options = requested;
  const auto grid = [&] {
    return planar_grid_size(options.max_translation, options.translation_step, options.max_rotation,
                            options.rotation_step);
  };
  for (int level = 0; grid() > std::max<std::size_t>(1, options.max_candidates) && level < 60; ++level) {
    options.translation_step *= 2.0;
    options.rotation_step *= 2.0;
    options.coarse_tolerance *= 2.0;
  }
  if (options.translation_step > requested.translation_step)
    options.radii.insert(options.radii.begin(), options.translation_step);
  std::vector<Pose> unique;
  for (const Pose& c : centres)
    if (std::none_of(unique.begin(), unique.end(), [&](const Pose& u) { return c.isApprox(u, 1e-9); }))
      unique.push_back(c);
  std::vector<Pose> candidates;
  for (const Pose& centre : unique)
    for (double yaw : offsets(options.max_rotation, options.rotation_step))
      for (double dx : offsets(options.max_translation, options.translation_step)) {
        Pose offset = Pose::Identity();
        offset.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
        offset.translation() = Vec3(dx, 0.0, 0.0);
        candidates.push_back(centre * offset);
      }
  StepSearchResult best;
  best.candidates = candidates.size();
  if (candidates.empty()) return best;
  std::vector<double> coarse(candidates.size());
  tbb::parallel_for(std::size_t{0}, candidates.size(),
                    [&](std::size_t i) { coarse[i] = score(candidates[i], options.coarse_tolerance); });
  std::vector<std::size_t> order(candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return coarse[a] > coarse[b]; });
  order.resize(std::min(order.size(), std::max<std::size_t>(1, options.refine)));
  // Each centre is also registered with the stages after the first alone: a nearly right
  // prediction stays where it is, where the widest radius can pull it onto an object that moved
  // (a vehicle beside the sensor) or a structure one spacing along (a row of posts).
  struct Start {
    Pose T;
    std::size_t first_stage;
  };
  std::vector<Start> starts;
  for (const std::size_t i : order) starts.push_back({candidates[i], 0});
  if (options.radii.size() > 1)
    for (const Pose& centre : unique) starts.push_back({centre, 1});
  std::vector<Pose> refined(starts.size());
  std::vector<double> fine(starts.size());
  tbb::parallel_for(std::size_t{0}, starts.size(), [&](std::size_t k) {
    Pose T = starts[k].T;
    for (std::size_t r = starts[k].first_stage; r < options.radii.size(); ++r)
      T = register_features(source, target, T, stage_params(options.radii[r], options.iterations)).T;
    refined[k] = T;
    fine[k] = score(T, options.fine_tolerance);
  });
  for (std::size_t k = 0; k < starts.size(); ++k) {
    if (k == 0 || fine[k] > best.fitness) {
      best.fitness = fine[k];
      best.T = refined[k];
    }
  }
  return best;
}

}  // namespace dloam
