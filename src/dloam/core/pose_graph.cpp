// Pose-graph optimisation with Ceres: one quaternion + translation block per node, one autodiff
// relative-pose residual per edge, whitened by the square root of its information.
#include "dloam/core/pose_graph.hpp"

#include <ceres/ceres.h>

#include <stdexcept>
#include <string>

namespace dloam {

namespace {

struct RelativePoseError {
  RelativePoseError(const Pose& z, const Mat6& sqrt_information)
      : q_z(z.rotation()), t_z(z.translation()), sqrt_info(sqrt_information) {}

  template <class T>
  bool operator()(const T* qa_ptr, const T* ta_ptr, const T* qb_ptr, const T* tb_ptr, T* res_ptr) const {
    Eigen::Map<const Eigen::Quaternion<T>> qa(qa_ptr), qb(qb_ptr);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(ta_ptr), tb(tb_ptr);
    const Eigen::Quaternion<T> qa_inv = qa.conjugate();
    const Eigen::Quaternion<T> q_ab = qa_inv * qb;
    const Eigen::Matrix<T, 3, 1> t_ab = qa_inv * (tb - ta);
    const Eigen::Quaternion<T> q_z_inv = q_z.conjugate().template cast<T>();
    const Eigen::Quaternion<T> dq = q_z_inv * q_ab;
    Eigen::Matrix<T, 6, 1> r;
    r.template head<3>() = T(2.0) * dq.vec();
    r.template tail<3>() = q_z_inv * (t_ab - t_z.template cast<T>());
    Eigen::Map<Eigen::Matrix<T, 6, 1>> residual(res_ptr);
    residual = sqrt_info.template cast<T>() * r;
    return true;
  }

  Eigen::Quaterniond q_z;
  Vec3 t_z;
  Mat6 sqrt_info;
};

}  // namespace

Mat6 information_from_sigmas(double sigma_rotation, double sigma_translation) {
  Vec6 d;
  d.head<3>().setConstant(1.0 / (sigma_rotation * sigma_rotation));
  d.tail<3>().setConstant(1.0 / (sigma_translation * sigma_translation));
  return d.asDiagonal();
}

std::vector<Pose> optimize_pose_graph(const std::vector<Pose>& poses, const std::vector<PoseGraphEdge>& edges,
                                      const PoseGraphOptions& options, PoseGraphSummary* summary) {
  const std::size_t n = poses.size();
  std::vector<Eigen::Quaterniond> q(n);
  std::vector<Vec3> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = Eigen::Quaterniond(poses[i].rotation()).normalized();
    t[i] = poses[i].translation();
  }

  // Declared before the problem, which borrows them.
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::HuberLoss loop_loss(options.loop_huber);
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const PoseGraphEdge& e : edges) {
    if (e.from >= n || e.to >= n || e.from == e.to)
      throw std::invalid_argument("pose graph: edge " + std::to_string(e.from) + " -> " +
                                  std::to_string(e.to) + " does not join two of the " + std::to_string(n) +
                                  " nodes");
    const Mat6 sqrt_info = e.information.llt().matrixU();
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 4, 3, 4, 3>(
        new RelativePoseError(e.measurement, sqrt_info));
    problem.AddResidualBlock(cost, e.loop ? &loop_loss : nullptr, q[e.from].coeffs().data(), t[e.from].data(),
                             q[e.to].coeffs().data(), t[e.to].data());
  }
  for (std::size_t i = 0; i < n; ++i)
    if (problem.HasParameterBlock(q[i].coeffs().data()))
      problem.SetManifold(q[i].coeffs().data(), &quaternion_manifold);
  if (n > 0 && problem.HasParameterBlock(q[0].coeffs().data())) {
    problem.SetParameterBlockConstant(q[0].coeffs().data());
    problem.SetParameterBlockConstant(t[0].data());
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary s;
  if (problem.NumResidualBlocks() > 0) ceres::Solve(solver_options, &problem, &s);
  if (summary) {
    summary->initial_cost = s.initial_cost;
    summary->final_cost = s.final_cost;
    summary->iterations = static_cast<int>(s.iterations.size());
    summary->usable = s.IsSolutionUsable();
  }
  if (problem.NumResidualBlocks() > 0 && !s.IsSolutionUsable()) return poses;

  std::vector<Pose> out(n, Pose::Identity());
  for (std::size_t i = 0; i < n; ++i) {
    out[i].linear() = q[i].normalized().toRotationMatrix();
    out[i].translation() = t[i];
  }
  return out;
}

}  // namespace dloam
