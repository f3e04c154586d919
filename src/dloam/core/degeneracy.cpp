#include "dloam/core/degeneracy.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace dloam {

Vec6 to_scaled(const Vec6& twist, const DegeneracyConfig& config) {
  Vec6 s = twist;
  s.head<3>() *= config.rotation_radius;
  return s;
}

Vec6 from_scaled(const Vec6& scaled, const DegeneracyConfig& config) {
  Vec6 t = scaled;
  t.head<3>() /= config.rotation_radius;
  return t;
}

Mat6 to_scaled_normal_matrix(const Mat6& H, const DegeneracyConfig& config) {
  Mat6 S = H;
  S.topRows<3>() /= config.rotation_radius;
  S.leftCols<3>() /= config.rotation_radius;
  return S;
}

SecondOpinion second_opinion(const Degeneracy& odometry, const Eigen::Matrix3d& R) {
  Mat6 A = Mat6::Zero();  // scaled twists rotate block by block: [R omega * radius; R v]
  A.topLeftCorner<3, 3>() = R;
  A.bottomRightCorner<3, 3>() = R;
  return {A * odometry.scaled_normal_matrix() * A.transpose(), odometry.matches};
}

Degeneracy analyse_degeneracy(const Mat6& H, int matches, const DofMask& dof, const DegeneracyConfig& config,
                              const PriorError& prior, const SecondOpinion* second) {
  Degeneracy out;
  out.matches = matches;
  // A feature adds at most 1 to a translation (its unit normal or line normal along it), so the
  // share of the matches is defined for translations; for a rotation it would depend on the radius.
  const double share = config.min_fraction * matches;
  std::vector<int> free;
  for (int i = 0; i < 6; ++i)
    if (dof[static_cast<std::size_t>(i)]) free.push_back(i);
  out.free = static_cast<int>(free.size());
  if (free.empty()) return out;
  const Mat6 S = to_scaled_normal_matrix(H, config);
  const auto n = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd Hs(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b)
      Hs(a, b) = S(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Hs);
  // Groups: 0 unconstrained and held by the prior, 1 unconstrained, 2 constrained; each group in
  // ascending order.
  std::vector<std::pair<int, Eigen::Index>> order;
  for (Eigen::Index a = 0; a < n; ++a) {
    Vec6 v = Vec6::Zero();
    for (Eigen::Index b = 0; b < n; ++b) v(free[static_cast<std::size_t>(b)]) = es.eigenvectors()(b, a);
    const bool translation = v.tail<3>().norm() > v.head<3>().norm();
    const double threshold = translation ? std::max(config.min_features, share) : config.min_features;
    // The prior's possible error along v (scaled coordinates: rotations at rotation_radius).
    const double prior_error =
        v.head<3>().norm() * prior.rotation * config.rotation_radius + v.tail<3>().norm() * prior.translation;
    bool constrained = !(es.eigenvalues()(a) < threshold);
    if (!constrained && second && translation && config.odometry_min_features > 0.0 &&
        !(es.eigenvalues()(a) < config.min_features)) {
      const double seen = v.dot(second->scaled_normal_matrix * v);
      constrained = !(seen < std::max(config.odometry_min_features, config.min_fraction * second->matches));
    }
    order.emplace_back(constrained ? 2 : prior_error <= config.max_prior_error ? 0 : 1, a);
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto [group, a] = order[static_cast<std::size_t>(k)];
    out.unconstrained += group < 2;
    out.held += group == 0;
    out.eigenvalues(k) = es.eigenvalues()(a);
    for (Eigen::Index b = 0; b < n; ++b)
      out.eigenvectors(free[static_cast<std::size_t>(b)], k) = es.eigenvectors()(b, a);
  }
  return out;
}

std::string direction_name(const Vec6& scaled) {
  static constexpr std::array<const char*, 6> kNames = {"roll", "pitch", "yaw", "x", "y", "z"};
  Eigen::Index i = 0;
  scaled.cwiseAbs().maxCoeff(&i);
  return kNames[static_cast<std::size_t>(i)];
}

std::string unconstrained_names(const Degeneracy& d) {
  std::string out;
  for (int a = 0; a < d.unconstrained; ++a) out += (a ? "+" : "") + direction_name(d.eigenvectors.col(a));
  return out;
}

}  // namespace dloam
