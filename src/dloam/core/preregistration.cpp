#include "dloam/core/preregistration.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "dloam/core/se3.hpp"
#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {
/// Eigen-decomposition of a covariance into a Pca (eigenvalues normalised to sum 1, descending).
Pca pca_of_covariance(const Eigen::Matrix3d& cov) {
  Pca out;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);  // ascending eigenvalues
  const Vec3 ev = es.eigenvalues().cwiseMax(0.0);
  const double sum = ev.sum();
  if (!(sum > 0.0)) return out;
  out.lambda = Vec3(ev(2), ev(1), ev(0)) / sum;
  out.e1 = es.eigenvectors().col(2);
  out.e2 = es.eigenvectors().col(1);
  out.e3 = es.eigenvectors().col(0);
  return out;
}

ObjectShape classify_pca(const Pca& pca, const Vec3& n, const PreRegistrationConfig& c) {
  if (pca.lambda(0) > c.xi_1 && pca.lambda(1) < c.xi_2 && std::abs(pca.e1.dot(n)) > c.xi_3)
    return ObjectShape::kPole;
  if (pca.lambda(2) < c.xi_4 && pca.lambda(1) >= c.xi_2 && std::abs(pca.e3.dot(n)) < c.xi_5)
    return ObjectShape::kPlane;
  return ObjectShape::kOther;
}
}  // namespace

Pca principal_components(const std::vector<Vec3>& points) {
  Pca out;
  if (points.size() < 3) return out;
  Vec3 mean = Vec3::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  return pca_of_covariance(cov);
}

ObjectShape classify_object(const std::vector<Vec3>& points, const Vec3& ground_normal,
                            const PreRegistrationConfig& c) {
  if (static_cast<int>(points.size()) < c.N_PCA) return ObjectShape::kOther;
  return classify_pca(principal_components(points), ground_normal.normalized(), c);
}

ObjectSet extract_objects(const std::vector<Vec3>& points, const SegmentationResult& seg,
                          const PreRegistrationConfig& config, double leaf) {
  // One pass accumulates each cluster's moments (count, sum, sum of outer products) for its PCA;
  // a second gathers the points of the clusters classified as poles or planes.
  const auto m = static_cast<std::size_t>(seg.num_clusters) + 1;
  std::vector<int> count(m, 0);
  std::vector<Vec3> sum(m, Vec3::Zero());
  std::vector<Eigen::Matrix3d> outer(m, Eigen::Matrix3d::Zero());
  for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
    const int l = seg.pixel_label[px];
    const int i = seg.image.point_of_pixel[px];
    if (l <= 0 || i < 0) continue;
    const Vec3& p = points[static_cast<std::size_t>(i)];
    const auto c = static_cast<std::size_t>(l);
    ++count[c];
    sum[c] += p;
    outer[c].selfadjointView<Eigen::Lower>().rankUpdate(p);
  }
  const Vec3 n = seg.ground_normal.normalized();
  std::vector<ObjectShape> shape(m, ObjectShape::kOther);
  ObjectSet out;
  for (std::size_t c = 1; c < m; ++c) {
    if (count[c] < std::max(3, config.N_PCA)) continue;
    const Vec3 mean = sum[c] / count[c];
    const Eigen::Matrix3d cov = Eigen::Matrix3d(outer[c].selfadjointView<Eigen::Lower>()) -
                                static_cast<double>(count[c]) * mean * mean.transpose();
    shape[c] = classify_pca(pca_of_covariance(cov), n, config);
    out.num_poles += shape[c] == ObjectShape::kPole;
    out.num_planes += shape[c] == ObjectShape::kPlane;
  }
  for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
    const int l = seg.pixel_label[px];
    const int i = seg.image.point_of_pixel[px];
    if (l <= 0 || i < 0) continue;
    const ObjectShape s = shape[static_cast<std::size_t>(l)];
    if (s == ObjectShape::kPole) out.poles.push_back(points[static_cast<std::size_t>(i)]);
    if (s == ObjectShape::kPlane) out.planes.push_back(points[static_cast<std::size_t>(i)]);
  }
  out.poles = voxel_downsample_points(out.poles, 0.5 * leaf);  // thin objects: keep more of them
  out.planes = voxel_downsample_points(out.planes, leaf);
  return out;
}

namespace {
/// Every k-th point so that at most `max_points` remain (deterministic).
std::vector<Vec3> thin(const std::vector<Vec3>& v, std::size_t max_points) {
  if (v.size() <= max_points) return v;
  const std::size_t step = (v.size() + max_points - 1) / max_points;
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < v.size(); i += step) out.push_back(v[i]);
  return out;
}
}  // namespace

CoarseResult trimmed_registration(const FeatureSource& source, const FeatureMap& target, const Pose& initial,
                                  int iterations, double trim_ratio, const RegistrationParams& params) {
  CoarseResult out;
  out.T = initial;
  FeatureSource src = with_unit_weights(source);
  const std::size_t n = src.edges.size() + src.planes.size();
  auto weight = [&](std::size_t i) -> double& { return feature_weight(src, i); };
  std::vector<std::size_t> active;
  for (std::size_t i = 0; i < n; ++i)
    if (weight(i) > 0.0) active.push_back(i);
  for (int it = 0; it < iterations && !active.empty(); ++it) {
    const RegistrationResult r = register_features(src, target, out.T, params);
    out.T = r.T;
    out.matches = r.edge_matches + r.plane_matches;
    if (it + 1 == iterations) break;
    // Drop the worst trim_ratio of the active points: unmatched first, then the largest residuals.
    auto bad = [&](std::size_t i) { return r.residuals[i] < 0.0 ? 1e30 : r.residuals[i]; };
    const auto drop = static_cast<std::size_t>(std::ceil(trim_ratio * static_cast<double>(active.size())));
    std::stable_sort(active.begin(), active.end(),
                     [&](std::size_t a, std::size_t b) { return bad(a) > bad(b); });
    for (std::size_t k = 0; k < drop && k < active.size(); ++k) weight(active[k]) = 0.0;
    active.erase(active.begin(), active.begin() + static_cast<long>(std::min(drop, active.size())));
    std::sort(active.begin(), active.end());
  }
  out.kept = active.size();
  out.valid = out.matches >= 30;
  return out;
}

Pose search_forward_translation(const Pose& initial, double range, double step,
                                const std::function<double(const Pose&)>& score) {
  return search_planar_motion(initial, range, step, 0.0, 0.0, score);
}

std::size_t planar_grid_size(double range, double step, double yaw_range, double yaw_step) {
  const double steps = step > 0.0 ? std::floor(range / step) : 0.0;
  const double turns = yaw_step > 0.0 ? std::floor(yaw_range / yaw_step + 1e-9) : 0.0;
  const double n = (2.0 * steps + 1.0) * (2.0 * turns + 1.0);
  return n < 1e15 ? static_cast<std::size_t>(n) : std::size_t{1000000000000000};
}

Pose search_planar_motion_bounded(
    const Pose& initial, double range, double step, double yaw_range, double yaw_step,
    std::size_t max_candidates, const std::function<std::function<double(const Pose&)>(double)>& score_for) {
  int levels = 0;
  double s = step, a = yaw_step;
  while (planar_grid_size(range, s, yaw_range, a) > std::max<std::size_t>(1, max_candidates) && levels < 60)
    s *= 2.0, a *= 2.0, ++levels;
  Pose best = search_planar_motion(initial, range, s, yaw_range, a, score_for(s));
  for (; levels > 0; --levels) {  // around the best, within one step of the level above
    best = search_planar_motion(best, s, 0.5 * s, a, 0.5 * a, score_for(0.5 * s));
    s *= 0.5, a *= 0.5;
  }
  return best;
}

Pose search_planar_motion(const Pose& initial, double range, double step, double yaw_range, double yaw_step,
                          const std::function<double(const Pose&)>& score) {
  const int steps = step > 0.0 ? static_cast<int>(std::floor(range / step)) : 0;
  const int turns = yaw_step > 0.0 ? static_cast<int>(std::floor(yaw_range / yaw_step + 1e-9)) : 0;
  const int width = 2 * steps + 1;
  const auto candidate = [&](int j, int k) {
    Pose T = initial;
    if (j != 0) T.linear() = T.linear() * Eigen::AngleAxisd(j * yaw_step, Vec3::UnitZ()).toRotationMatrix();
    T.translation() += Vec3(k * step, 0.0, 0.0);
    return T;
  };
  // The candidates are independent (a full-image score each): scored in parallel, chosen in order.
  std::vector<double> scores(static_cast<std::size_t>((2 * turns + 1) * width));
  tbb::parallel_for(0, static_cast<int>(scores.size()), [&](int c) {
    scores[static_cast<std::size_t>(c)] = score(candidate(c / width - turns, c % width - steps));
  });
  int best_j = 0, best_k = 0;
  double best_score = -1.0;
  for (int j = -turns; j <= turns; ++j) {
    for (int k = -steps; k <= steps; ++k) {
      const double s = scores[static_cast<std::size_t>((j + turns) * width + k + steps)];
      const bool tie =
          s == best_score && (std::abs(j) < std::abs(best_j) ||
                              (std::abs(j) == std::abs(best_j) && std::abs(k) < std::abs(best_k)));
      if (s > best_score || tie) {
        best_score = s;
        best_j = j;
        best_k = k;
      }
    }
  }
  return candidate(best_j, best_k);
}

CoarseResult coarse_motion(const ObjectSet& current, const FeatureMap& target, const Pose& predicted,
                           const PreRegistrationConfig& config, const MotionGate* gate) {
  RegistrationParams p;
  p.max_iterations = 2;  // per round; the rounds continue from the previous estimate
  p.max_correspondence = 1.0;
  p.huber = 0.2;
  p.prior = predicted;  // directions the objects do not constrain keep the prediction
  // The source needs only a few hundred points per object type; the target keeps all.
  FeatureSource src{thin(current.poles, 300), thin(current.planes, 400), {}, {}};
  CoarseResult r =
      trimmed_registration(src, target, predicted, std::max(1, config.N_coarse), config.trim_ratio, p);
  if (gate && !gate->admits(predicted.inverse() * r.T)) r.valid = false;
  if (!r.valid) r.T = predicted;
  return r;
}

}  // namespace dloam
