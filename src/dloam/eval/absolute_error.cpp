// ATE (unaligned and SE(3)-aligned with Eigen::umeyama) and per-frame RPE.
#include "dloam/eval/absolute_error.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "dloam/eval/relative_error.hpp"

namespace dloam::eval {
namespace {

void check_sizes(const std::vector<Pose>& gt, const std::vector<Pose>& est, const char* what) {
  if (gt.size() != est.size()) {
    throw InputError(std::string(what) + ": ground truth has " + std::to_string(gt.size()) +
                     " poses but the estimate has " + std::to_string(est.size()));
  }
  if (gt.empty()) throw InputError(std::string(what) + ": the trajectories are empty");
}

ErrorStats position_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est, const Pose& transform) {
  std::vector<double> errors;
  errors.reserve(gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    errors.push_back((gt[i].translation() - transform * est[i].translation()).norm());
  }
  return error_stats(errors);
}

}  // namespace

ErrorStats error_stats(const std::vector<double>& errors) {
  ErrorStats stats;
  stats.count = errors.size();
  if (errors.empty()) return stats;
  double sum = 0.0, sum_sq = 0.0;
  for (const double e : errors) {
    sum += e;
    sum_sq += e * e;
    stats.max = std::max(stats.max, e);
  }
  const double n = static_cast<double>(errors.size());
  stats.mean = sum / n;
  stats.rmse = std::sqrt(sum_sq / n);
  return stats;
}

ErrorStats ate(const std::vector<Pose>& gt, const std::vector<Pose>& est) {
  check_sizes(gt, est, "ATE");
  return position_errors(gt, est, Pose::Identity());
}

Pose align_positions(const std::vector<Pose>& gt, const std::vector<Pose>& est) {
  check_sizes(gt, est, "ATE alignment");
  Eigen::Matrix3Xd src(3, est.size());
  Eigen::Matrix3Xd dst(3, gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = est[i].translation();
    dst.col(static_cast<Eigen::Index>(i)) = gt[i].translation();
  }
  Pose transform = Pose::Identity();
  if (gt.size() >= 2)
    transform.matrix() = Eigen::umeyama(src, dst, false);
  else
    transform.translation() = dst.col(0) - src.col(0);
  return transform;
}

ErrorStats ate_aligned(const std::vector<Pose>& gt, const std::vector<Pose>& est) {
  return position_errors(gt, est, align_positions(gt, est));
}

Rpe rpe(const std::vector<Pose>& gt, const std::vector<Pose>& est) {
  check_sizes(gt, est, "RPE");
  std::vector<double> trans, rot;
  std::size_t tracked = 0;
  for (std::size_t i = 0; i + 1 < gt.size(); ++i) {
    const Pose error = between(between(gt[i], gt[i + 1]), between(est[i], est[i + 1]));
    trans.push_back(error.translation().norm());
    rot.push_back(rotation_angle(error) * 180.0 / M_PI);
    tracked += trans.back() < kTrackedStepM && rot.back() < kTrackedStepDeg;
  }
  return {error_stats(trans), error_stats(rot), trans.size(), tracked};
}

}  // namespace dloam::eval
