#include "dloam/core/registration.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace dloam {

namespace {

using Mat36 = Eigen::Matrix<double, 3, 6>;
using Vec6Row = Eigen::Matrix<double, 1, 6>;

/// One linearised residual: contribution to J^T W J and J^T W r.
struct Term {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double residual = -1.0;  ///< |r|, -1 when unmatched
};

/// d(c + exp(delta) (q - c))/d(delta) at delta = 0 for the twist order [omega; v]: the perturbation
/// rotates about the centre c (the current sensor position, see register_features).
Mat36 point_jacobian(const Vec3& q, const Vec3& c) {
  Mat36 J;
  J.leftCols<3>() = -hat(q - c);
  J.rightCols<3>() = Eigen::Matrix3d::Identity();
  return J;
}

using Mat6Dyn = Eigen::Matrix<double, 6, Eigen::Dynamic>;

double huber_weight(double r, double k) { return r <= k ? 1.0 : k / r; }

/// The motion exp(delta) with its rotation about c: p -> c + exp(delta) (p - c).
Pose step_about(const Vec6& delta, const Vec3& c) {
  Pose step = exp_se3(delta);
  step.translation() += c - step.linear() * c;
  return step;
}

/// The twist delta with step_about(delta, c) == M.
Vec6 twist_about(const Pose& M, const Vec3& c) {
  Pose about_origin = M;
  about_origin.translation() = M.translation() - c + M.linear() * c;
  return log_se3(about_origin);
}

/// Mean and covariance eigen-decomposition (ascending eigenvalues) of the neighbours.
struct Neighbourhood {
  Vec3 mean;
  Eigen::Vector3d eigenvalues;
  Eigen::Matrix3d eigenvectors;
};

bool neighbourhood(const KdTree& tree, const Vec3& q, const RegistrationParams& p, Neighbourhood& out) {
  std::array<std::uint32_t, 16> idx{};
  std::array<double, 16> d2{};
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(p.neighbours), idx.size());
  const std::size_t found = tree.knn(q, k, idx.data(), d2.data());
  if (found < k || d2[found - 1] > p.max_correspondence * p.max_correspondence) return false;
  const auto& pts = tree.points();
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 0; i < found; ++i) mean += pts[idx[i]];
  mean /= static_cast<double>(found);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < found; ++i) {
    const Vec3 d = pts[idx[i]] - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov / static_cast<double>(found));
  out = {mean, es.eigenvalues(), es.eigenvectors()};
  return true;
}

/// A feature's correspondence: the line (edge) or plane fitted to its neighbours in the target.
struct Association {
  bool valid = false;
  Vec3 mean = Vec3::Zero();
  Vec3 direction = Vec3::Zero();  ///< line direction (edge) or plane normal (plane)
};

Association associate_edge(const Vec3& q, const KdTree& tree, const RegistrationParams& p) {
  Neighbourhood n;
  if (!neighbourhood(tree, q, p, n)) return {};
  if (n.eigenvalues(2) < p.min_line_ratio * n.eigenvalues(1)) return {};  // neighbours do not form a line
  return {true, n.mean, n.eigenvectors.col(2)};
}

Association associate_plane(const Vec3& q, const KdTree& tree, const RegistrationParams& p) {
  Neighbourhood n;
  if (!neighbourhood(tree, q, p, n)) return {};
  // A plane: the smallest spread is small both absolutely and relative to the others.
  if (n.eigenvalues(0) > 0.01 || n.eigenvalues(0) > 0.1 * n.eigenvalues(1)) return {};
  // ... and spans a patch, not one scan ring: along a ring the neighbours spread in one direction
  // only, their range noise tilts the fitted normal towards the sensor, and the plane step of the
  // odometry picked up a steady pitch bias from it (0.044 deg per scan on a simulated street).
  // Rejected: spread across below 0.22 times the spread along.
  if (n.eigenvalues(1) < 0.05 * n.eigenvalues(2)) return {};
  return {true, n.mean, n.eigenvectors.col(0)};
}

Term edge_term(const Vec3& q, const Vec3& c, double w, const Association& a, const RegistrationParams& p) {
  Term t;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - a.direction * a.direction.transpose();
  const Vec3 r = P * (q - a.mean);
  const Mat36 J = P * point_jacobian(q, c);
  t.residual = r.norm();
  const double ww = w * huber_weight(t.residual, p.huber);
  t.H = ww * J.transpose() * J;
  t.g = ww * J.transpose() * r;
  return t;
}

Term plane_term(const Vec3& q, const Vec3& c, double w, const Association& a, const RegistrationParams& p) {
  Term t;
  const double r = a.direction.dot(q - a.mean);
  const Vec6Row J = a.direction.transpose() * point_jacobian(q, c);
  t.residual = std::abs(r);
  const double ww = w * huber_weight(t.residual, p.huber);
  t.H = ww * J.transpose() * J;
  t.g = ww * J.transpose() * r;
  return t;
}

}  // namespace

FeatureSource with_unit_weights(FeatureSource src) {
  if (src.edge_weights.empty()) src.edge_weights.assign(src.edges.size(), 1.0);
  if (src.plane_weights.empty()) src.plane_weights.assign(src.planes.size(), 1.0);
  return src;
}

RegistrationResult register_features(const FeatureSource& src, const FeatureMap& target, const Pose& initial,
                                     const RegistrationParams& params) {
  RegistrationResult res;
  res.T = initial;
  const std::size_t ne = src.edges.size();
  const std::size_t n = ne + src.planes.size();
  std::vector<Term> terms(n);
  std::vector<int> free;
  for (int i = 0; i < 6; ++i)
    if (params.dof[static_cast<std::size_t>(i)]) free.push_back(i);
  const auto nf = static_cast<Eigen::Index>(free.size());

  std::vector<Association> assoc(n);
  Pose associated_at;  // pose of the last association
  bool analysed = false;
  Mat6Dyn constrained;  // scaled twist directions the iterations move along
  for (int it = 0; it < params.max_iterations; ++it) {
    res.iterations = it + 1;
    const Pose T = res.T;
    // Rotations are about the sensor's current position, not the target frame's origin: far from
    // the origin a rotation about it is almost a translation, so J^T J would be ill-conditioned and
    // the degeneracy test would freeze well-constrained directions (e.g. z, and with it roll/pitch).
    const Vec3 c = T.translation();
    // Nearest-neighbour search only when the pose moved since the last association; once the
    // estimate settles, iterations re-linearise against the same lines and planes.
    const Pose moved = associated_at.inverse() * T;
    const bool reassociate = it == 0 || moved.translation().norm() > params.reassociate_translation ||
                             rotation_angle(moved) > params.reassociate_rotation;
    if (reassociate) associated_at = T;
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      const bool edge = i < ne;
      const auto& weights = edge ? src.edge_weights : src.plane_weights;
      const std::size_t j = edge ? i : i - ne;
      const double w = weights.empty() ? 1.0 : weights[j];
      terms[i] = Term{};
      if (w <= 0.0) return;
      const Vec3 q = T * (edge ? src.edges[j] : src.planes[j]);
      if (reassociate)
        assoc[i] = edge ? associate_edge(q, target.edges, params) : associate_plane(q, target.planes, params);
      if (assoc[i].valid)
        terms[i] = edge ? edge_term(q, c, w, assoc[i], params) : plane_term(q, c, w, assoc[i], params);
    });
    // Sequential sum: the result does not depend on the thread schedule.
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    res.edge_matches = res.plane_matches = 0;
    double sum_r = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (terms[i].residual < 0.0) continue;
      H += terms[i].H;
      g += terms[i].g;
      sum_r += terms[i].residual;
      (i < ne ? res.edge_matches : res.plane_matches)++;
    }
    const int matches = res.edge_matches + res.plane_matches;
    res.mean_residual = matches > 0 ? sum_r / matches : 0.0;
    res.normal_matrix = H;
    if (matches < 10) {  // too few correspondences to constrain the pose: the prior stands
      res.degeneracy = analyse_degeneracy(H, matches, params.dof, params.degeneracy);
      res.degeneracy.unconstrained = res.degeneracy.held = res.degeneracy.free;
      if (params.prior && nf > 0) res.T = *params.prior;
      break;
    }
    if (nf == 0) break;  // only the residuals at `initial` were asked for

    const DegeneracyConfig& dc = params.degeneracy;
    if (!analysed) {
      // The unconstrained directions at the initial guess (Zhang, Kaess & Singh 2016). They stay
      // fixed: re-deciding at every iteration let the estimate creep along a weak direction.
      analysed = true;
      res.degeneracy = analyse_degeneracy(H, matches, params.dof, dc, params.prior_error,
                                          params.second_opinion ? &*params.second_opinion : nullptr);
      // The directions held by the prior, then the ones the iterations move along: the constrained
      // ones and those unconstrained ones where the prior can be further off than the data.
      const int u = res.degeneracy.held;
      constrained = res.degeneracy.eigenvectors.middleCols(u, nf - u);
      if (u > 0 && params.prior) {
        // Solution remapping: along the held directions the estimate takes the prior's value,
        // then the iterations move it along the others only.
        const Mat6Dyn unconstrained = res.degeneracy.eigenvectors.leftCols(u);
        const Vec6 to_prior = to_scaled(twist_about(*params.prior * T.inverse(), c), dc);
        const Vec6 shift = unconstrained * (unconstrained.transpose() * to_prior);
        if (shift.norm() > 1e-9) {
          res.T = normalized(step_about(from_scaled(shift, dc), c) * res.T);
          continue;
        }
      }
    }
    if (constrained.cols() == 0) break;  // nothing the geometry constrains: the prior stands
    // Gauss-Newton over the constrained directions: H and g in scaled coordinates, projected.
    const Eigen::MatrixXd Hq = constrained.transpose() * to_scaled_normal_matrix(H, dc) * constrained;
    const Eigen::VectorXd gq = constrained.transpose() * from_scaled(g, dc);
    const Vec6 delta = from_scaled(-(constrained * Hq.ldlt().solve(gq)), dc);
    res.T = normalized(step_about(delta, c) * res.T);
    if (delta.head<3>().norm() < params.convergence_rotation &&
        delta.tail<3>().norm() < params.convergence_translation)
      break;
  }
  res.residuals.resize(n);
  for (std::size_t i = 0; i < n; ++i) res.residuals[i] = terms[i].residual;
  return res;
}

}  // namespace dloam
