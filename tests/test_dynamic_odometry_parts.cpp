// Odometry-side parts of the dynamic-object handling: eq. 15 weight compensation near dynamic
// objects and the RANSAC pseudo-static feature rejection (N_pseudo, beta).
#include <gtest/gtest.h>

#include <random>

#include "dloam/core/pseudo_static_rejection.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/weight_compensation.hpp"

using namespace dloam;

TEST(WeightCompensation, ColumnDistanceWrapsAndFactorFollowsEq15) {
  const int rows = 2, cols = 10;
  std::vector<std::uint8_t> dyn(static_cast<std::size_t>(rows * cols), 0);
  EXPECT_EQ(dynamic_column_distance(dyn, rows, cols), std::vector<int>(10, -1));
  dyn[static_cast<std::size_t>(1 * cols + 1)] = 1;  // a dynamic pixel in column 1
  EXPECT_EQ(dynamic_column_distance(dyn, rows, cols), (std::vector<int>{1, 0, 1, 2, 3, 4, 5, 4, 3, 2}));
  EXPECT_DOUBLE_EQ(compensation_factor(-1), 1.0);
  EXPECT_DOUBLE_EQ(compensation_factor(0), 0.0);
  EXPECT_DOUBLE_EQ(compensation_factor(1), 0.0);  // |theta| = r_horiz
  EXPECT_DOUBLE_EQ(compensation_factor(4), 0.75);
  RangeImage img;
  img.rows = rows;
  img.cols = cols;
  img.col_of_point = {1, 3, 6, -1};
  const auto w = compensated_weights({0, 1, 2, 3}, img, dynamic_column_distance(dyn, rows, cols));
  EXPECT_EQ(w, (std::vector<double>{0.0, 0.5, 0.8, 1.0}));
}

namespace {

/// Plane features on three orthogonal wall families, plus `moved` features on a box that moved.
struct Problem {
  FeatureMap target;
  FeatureSource source;
  std::size_t n_static = 0;
  Pose truth;
};

void make_problem(Problem& pb, double outlier_fraction) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> target;
  for (int i = 0; i < 9000; ++i) {
    const int f = i % 3;
    Vec3 p(8 * u(rng), 8 * u(rng), 1.5 * u(rng));
    p[f] = (i % 2 ? 10.0 : -10.0) * (f == 2 ? 0.2 : 1.0);
    target.push_back(p);
  }
  Vec6 xi;
  xi << 0.002, -0.001, 0.02, 0.3, -0.1, 0.02;
  pb.truth = exp_se3(xi);
  for (std::size_t i = 0; i < target.size(); i += 7)
    pb.source.planes.push_back(pb.truth.inverse() * target[i]);
  pb.n_static = pb.source.planes.size();
  // Pseudo-static features: points 0.3 m (along x) away from where the previous scan saw a surface,
  // spread over every wall, so the inliers dominate each direction.
  const auto n_out = static_cast<std::size_t>(outlier_fraction / (1 - outlier_fraction) * pb.n_static);
  for (std::size_t k = 0; k < n_out; ++k)
    pb.source.planes.push_back(pb.truth.inverse() * (target[(k * 11 + 1) % target.size()] + Vec3(0.3, 0, 0)));
  pb.target.planes.build(target);
  pb.target.edges.build({});
}

}  // namespace

TEST(PseudoStaticRejection, RemovesWorstFeaturesAndImprovesThePose) {
  Problem pb;
  make_problem(pb, 0.2);
  RegistrationParams p;
  p.max_iterations = 20;
  p.max_correspondence = 1.0;
  p.huber = 1.0;  // a weak kernel, so the outliers pull the plain estimate
  // The rejection alone: in this room 20 m across, rotations counted at 20 m fall under the
  // scan-level threshold of 30 features' worth, which would keep them at the prior.
  p.degeneracy.min_features = 5.0;

  PoseEstimator estimate = [&](const FeatureSource& src, const Pose& init) {
    return register_features(src, pb.target, init, p);
  };
  const RejectionResult plain = reject_pseudo_static(pb.source, Pose::Identity(), 1, 0.1, 0.05, estimate);
  const RejectionResult rej = reject_pseudo_static(pb.source, Pose::Identity(), 5, 0.1, 0.05, estimate);
  const double e_plain = translation_norm(pb.truth.inverse() * plain.result.T);
  const double e_rej = translation_norm(pb.truth.inverse() * rej.result.T);
  std::printf("translation error: %.4f m plain, %.4f m after %d rounds (%zu removed)\n", e_plain, e_rej,
              rej.rounds, rej.removed);
  EXPECT_EQ(plain.rounds, 1);
  EXPECT_EQ(plain.removed, 0u);
  EXPECT_GT(rej.rounds, 1);
  EXPECT_LT(e_rej, 0.5 * e_plain);
  EXPECT_LT(e_rej, 0.01);
  // Most removed features are the pseudo-static ones.
  std::size_t removed_outliers = 0;
  for (std::size_t i = pb.n_static; i < rej.kept.size(); ++i) removed_outliers += !rej.kept[i];
  EXPECT_GT(removed_outliers, rej.removed / 2);
}

TEST(PseudoStaticRejection, StopsAfterOneRoundWithoutOutliers) {
  Problem pb;
  make_problem(pb, 0.0);
  RegistrationParams p;
  p.max_correspondence = 1.0;
  // The rejection alone: in this room 20 m across, rotations counted at 20 m fall under the
  // scan-level threshold of 30 features' worth, which would keep them at the prior.
  p.degeneracy.min_features = 5.0;
  int calls = 0;
  PoseEstimator estimate = [&](const FeatureSource& src, const Pose& init) {
    ++calls;
    return register_features(src, pb.target, init, p);
  };
  const RejectionResult r = reject_pseudo_static(pb.source, Pose::Identity(), 5, 0.1, 0.05, estimate);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(r.removed, 0u);
  EXPECT_LT(translation_norm(pb.truth.inverse() * r.result.T), 0.005);
}
