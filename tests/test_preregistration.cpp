// Pre-registration (paper III.D.1): PCA classification of synthetic poles / walls (eqs. 8-11) and
// the trimmed ICP recovering a known motion between object sets with 30 % outliers.
#include <gtest/gtest.h>

#include <atomic>
#include <random>

#include "dloam/core/preregistration.hpp"
#include "dloam/core/se3.hpp"

using namespace dloam;

namespace {

std::vector<Vec3> pole(const Vec3& base, const Vec3& axis, double radius, double length, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 a = axis.normalized();
  const Vec3 p = a.unitOrthogonal(), q = a.cross(p);
  std::vector<Vec3> out;
  for (int i = 0; i < 400; ++i) {
    const double phi = 2.0 * M_PI * u(rng);
    out.push_back(base + length * u(rng) * a + radius * (std::cos(phi) * p + std::sin(phi) * q));
  }
  return out;
}

/// A rectangle spanned by `w` x `h` around `corner` with Gaussian noise `sigma` along its normal.
std::vector<Vec3> patch(const Vec3& corner, const Vec3& w, const Vec3& h, double sigma, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, sigma);
  const Vec3 normal = w.cross(h).normalized();
  std::vector<Vec3> out;
  for (int i = 0; i < 1500; ++i) out.push_back(corner + u(rng) * w + u(rng) * h + n(rng) * normal);
  return out;
}

const Vec3 kUp = Vec3::UnitZ();

}  // namespace

TEST(Preregistration, PcaClassifiesPolesAndWalls) {
  std::mt19937 rng(1);
  PreRegistrationConfig c;
  EXPECT_EQ(classify_object(pole({5, 2, -1.7}, kUp, 0.1, 3.0, rng), kUp, c), ObjectShape::kPole);
  EXPECT_EQ(classify_object(patch({10, -3, -1.7}, {0, 6, 0}, {0, 0, 3}, 0.01, rng), kUp, c),
            ObjectShape::kPlane);
  // A wall seen at an angle in the xy-plane is still vertical.
  EXPECT_EQ(classify_object(patch({10, -3, -1.7}, {3, 4, 0}, {0, 0, 3}, 0.01, rng), kUp, c),
            ObjectShape::kPlane);
  // Ground patch (horizontal plane), leaning pole, blob, too few points: not reference objects.
  EXPECT_EQ(classify_object(patch({3, 3, -1.7}, {4, 0, 0}, {0, 4, 0}, 0.01, rng), kUp, c),
            ObjectShape::kOther);
  EXPECT_EQ(classify_object(pole({5, 2, -1.7}, {1, 0, 1}, 0.1, 3.0, rng), kUp, c), ObjectShape::kOther);
  EXPECT_EQ(classify_object(patch({3, 3, -1.7}, {2, 0, 0}, {0, 0, 1.5}, 0.5, rng), kUp, c),
            ObjectShape::kOther);
  auto few = pole({5, 2, -1.7}, kUp, 0.1, 3.0, rng);
  few.resize(static_cast<std::size_t>(c.N_PCA) - 1);
  EXPECT_EQ(classify_object(few, kUp, c), ObjectShape::kOther);
  // The same wall with a tilted ground normal (sensor pitched 20 deg) is no longer vertical.
  const Vec3 tilted = Eigen::AngleAxisd(20.0 * M_PI / 180.0, Vec3::UnitY()) * kUp;
  EXPECT_EQ(classify_object(patch({10, -3, -1.7}, {0, 6, 0}, {0, 0, 3}, 0.01, rng), tilted, c),
            ObjectShape::kOther);
}

TEST(Preregistration, TrimmedIcpRecoversMotionWith30PercentOutliers) {
  std::mt19937 rng(7);
  // Static reference objects in the previous frame: poles and walls in several directions.
  std::vector<Vec3> poles, planes;
  for (const Vec3& b : {Vec3(6, 3, -1.7), Vec3(-4, 5, -1.7), Vec3(12, -6, -1.7), Vec3(-9, -4, -1.7)}) {
    const auto p = pole(b, kUp, 0.08, 4.0, rng);
    poles.insert(poles.end(), p.begin(), p.end());
  }
  for (const auto& w : {patch({15, -8, -1.7}, {0, 16, 0}, {0, 0, 4}, 0.01, rng),
                        patch({-12, -8, -1.7}, {0, 16, 0}, {0, 0, 4}, 0.01, rng),
                        patch({-6, 9, -1.7}, {14, 0, 0}, {0, 0, 4}, 0.01, rng),
                        patch({-6, -11, -1.7}, {10, 3, 0}, {0, 0, 4}, 0.01, rng)})
    planes.insert(planes.end(), w.begin(), w.end());
  FeatureMap target;
  target.edges.build(poles);
  target.planes.build(planes);

  // The current scan: the same objects seen after a motion, plus 30 % outliers: a moving car side
  // 0.6 m in front of a wall, a pedestrian next to a pole, and clutter.
  Vec6 xi;
  xi << 0.004, -0.003, 0.03, 0.45, 0.06, 0.0;  // vertical objects do not constrain t_z
  const Pose truth = exp_se3(xi);              // current -> previous
  const Pose inv = truth.inverse();
  FeatureSource src;
  for (std::size_t i = 0; i < poles.size(); i += 4) src.edges.push_back(inv * poles[i]);
  for (std::size_t i = 0; i < planes.size(); i += 8) src.planes.push_back(inv * planes[i]);
  const std::size_t inliers = src.edges.size() + src.planes.size();
  const auto n_out = static_cast<std::size_t>(0.3 / 0.7 * static_cast<double>(inliers));
  const auto car = patch({14.4, -6, -1.2}, {0, 4, 0}, {0, 0, 1.4}, 0.01, rng);
  const auto person = pole({5.6, 2.7, -1.7}, kUp, 0.25, 1.8, rng);
  std::uniform_real_distribution<double> u(-15.0, 15.0);
  for (std::size_t k = 0; k < n_out; ++k) {
    if (k % 3 == 0)
      src.edges.push_back(person[k % person.size()]);
    else if (k % 3 == 1)
      src.planes.push_back(car[k % car.size()]);
    else
      src.planes.push_back(Vec3(u(rng), u(rng), 0.1 * u(rng)));
  }
  RegistrationParams p;
  p.max_iterations = 10;
  p.max_correspondence = 1.0;
  p.huber = 0.2;
  Vec6 off;
  off << 0, 0, 0.01, 0.3, 0, 0;  // a constant-velocity prediction 0.3 m / 0.6 deg off
  const Pose start = exp_se3(xi - off);
  const CoarseResult plain = trimmed_registration(src, target, start, 1, 0.0, p);
  const CoarseResult trimmed = trimmed_registration(src, target, start, 5, 0.1, p);
  const Pose err_plain = truth.inverse() * plain.T, err = truth.inverse() * trimmed.T;
  std::printf("plain ICP: %.3f m %.3f deg; trimmed x5: %.3f m %.3f deg (kept %zu of %zu)\n",
              translation_norm(err_plain), rotation_angle(err_plain) * 180 / M_PI, translation_norm(err),
              rotation_angle(err) * 180 / M_PI, trimmed.kept, inliers + n_out);
  // Vertical objects leave t_z to the prediction: check the horizontal motion and the rotation.
  const double xy = err.translation().head<2>().norm(), xy_plain = err_plain.translation().head<2>().norm();
  std::printf("horizontal error: %.4f m plain, %.4f m trimmed\n", xy_plain, xy);
  EXPECT_TRUE(trimmed.valid);
  EXPECT_LT(xy, 0.02);
  EXPECT_LT(rotation_angle(err) * 180 / M_PI, 0.15);
  EXPECT_LE(xy, xy_plain);
  EXPECT_LT(trimmed.kept, inliers + n_out);
}

TEST(Preregistration, CoarseMotionFallsBackToPredictionWithoutObjects) {
  FeatureMap empty;
  empty.edges.build({});
  empty.planes.build({});
  Vec6 xi;
  xi << 0, 0, 0.01, 0.4, 0, 0;
  const Pose predicted = exp_se3(xi);
  const CoarseResult r = coarse_motion(ObjectSet{}, empty, predicted, PreRegistrationConfig{}, nullptr);
  EXPECT_FALSE(r.valid);
  EXPECT_TRUE(r.T.isApprox(predicted));
}

TEST(Preregistration, CoarseMotionOutsideTheMotionGateIsRejected) {
  // Poles and walls that pin the motion; the current scan is 0.25 m / 0.8 deg (yaw) or 0.6 m
  // away from the prediction. Within the gate the ICP result is kept, beyond it the prediction.
  std::mt19937 rng(3);
  ObjectSet previous;
  for (const Vec3& b : {Vec3(6, 3, -1.7), Vec3(-4, 5, -1.7), Vec3(12, -6, -1.7), Vec3(-9, -4, -1.7)}) {
    const auto p = pole(b, kUp, 0.08, 4.0, rng);
    previous.poles.insert(previous.poles.end(), p.begin(), p.end());
  }
  for (const auto& w : {patch({15, -8, -1.7}, {0, 16, 0}, {0, 0, 4}, 0.01, rng),
                        patch({-6, 9, -1.7}, {14, 0, 0}, {0, 0, 4}, 0.01, rng)})
    previous.planes.insert(previous.planes.end(), w.begin(), w.end());
  FeatureMap target;
  target.edges.build(previous.poles);
  target.planes.build(previous.planes);
  const auto seen_after = [&](const Pose& truth) {
    ObjectSet current;
    for (const Vec3& q : previous.poles) current.poles.push_back(truth.inverse() * q);
    for (const Vec3& q : previous.planes) current.planes.push_back(truth.inverse() * q);
    return current;
  };
  Vec6 xi;
  xi << 0, 0, 0, 2.5, 0, 0;
  const Pose predicted = exp_se3(xi);
  PreRegistrationConfig c;
  MotionModel model{MotionConfig{}};  // the car platform: at 10 Hz a 0.3 m / 1 deg gate
  model.update(predicted, 0.1);
  MotionGate gate = model.gate(0.1);
  Vec6 small;
  small << 0, 0, 0.8 * M_PI / 180.0, -0.25, 0.05, 0;
  const Pose near_truth = predicted * exp_se3(small);
  const CoarseResult kept = coarse_motion(seen_after(near_truth), target, predicted, c, &gate);
  EXPECT_TRUE(kept.valid);
  EXPECT_LT(translation_norm(near_truth.inverse() * kept.T), 0.02);

  Vec6 jump;
  jump << 0, 0, 0, -0.6, 0, 0;
  const Pose far_truth = predicted * exp_se3(jump);
  const CoarseResult rejected = coarse_motion(seen_after(far_truth), target, predicted, c, &gate);
  EXPECT_FALSE(rejected.valid);
  EXPECT_TRUE(rejected.T.isApprox(predicted));
  // Ungated (the first scan pair: its start is a search result, no prior) it is kept.
  const CoarseResult ungated = coarse_motion(seen_after(far_truth), target, predicted, c, nullptr);
  EXPECT_TRUE(ungated.valid);
  EXPECT_LT(translation_norm(far_truth.inverse() * ungated.T), 0.02);
  EXPECT_TRUE(gate.admits(predicted.inverse() * near_truth));
  EXPECT_FALSE(gate.admits(predicted.inverse() * far_truth));
  // Three scans later (two dropped), the platform's accelerations allow much more: the same
  // registration is let through.
  const MotionGate wide_gate = model.gate(0.3);
  EXPECT_GT(wide_gate.max_translation, 0.6);
  EXPECT_TRUE(wide_gate.admits(predicted.inverse() * far_truth));
  const CoarseResult wide = coarse_motion(seen_after(far_truth), target, predicted, c, &wide_gate);
  EXPECT_TRUE(wide.valid);
  EXPECT_LT(translation_norm(far_truth.inverse() * wide.T), 0.02);
}

TEST(Preregistration, ForwardSearchTakesTheBestScoreAndTheSmallestTie) {
  Vec6 xi;
  xi << 0, 0, 0.02, 0.1, 0.05, 0;
  const Pose initial = exp_se3(xi);
  // A score with its maximum 1.4 m ahead of `initial`.
  auto peak = [&](const Pose& T) { return -std::abs(T.translation().x() - initial.translation().x() - 1.4); };
  const Pose found = search_forward_translation(initial, 3.0, 0.2, peak);
  EXPECT_NEAR(found.translation().x() - initial.translation().x(), 1.4, 1e-9);
  EXPECT_TRUE(found.linear().isApprox(initial.linear()));
  EXPECT_NEAR(found.translation().y(), initial.translation().y(), 1e-12);
  // A flat score (nothing matches): the prior itself.
  const Pose flat = search_forward_translation(initial, 3.0, 0.2, [](const Pose&) { return 0.0; });
  EXPECT_TRUE(flat.isApprox(initial));
}

TEST(Preregistration, ASearchOverALongIntervalScoresABoundedNumberOfCandidates) {
  // Scans dropped for 4 s before the second one: at 40 m/s and 60 deg/s the ranges are 164 m and
  // 180 deg, 200 k candidates at the first pair's coarse steps (0.4 m, 2 deg).
  const Pose initial = Pose::Identity();
  const double dx = 37.3, yaw = 1.1;  // the motion to find
  std::atomic<std::size_t> calls{0};
  const auto score_for = [&](double tolerance) {
    return [&, tolerance](const Pose& T) {
      ++calls;
      const double a = std::atan2(T.linear()(1, 0), T.linear()(0, 0));
      // Scores are shares (>= 0), highest at the motion; the tolerance plays no part here.
      return 1.0 / (1.0 + std::abs(T.translation().x() - dx) + 10.0 * std::abs(a - yaw)) + 0.0 * tolerance;
    };
  };
  constexpr double kStep = 0.4, kTurn = 2.0 * M_PI / 180.0;
  EXPECT_GT(planar_grid_size(164.0, kStep, M_PI, kTurn), 100000u);
  const Pose found = search_planar_motion_bounded(initial, 164.0, kStep, M_PI, kTurn, 4000, score_for);
  EXPECT_LE(calls.load(), 4000u + 8u * 25u);  // the first level, then 5 x 5 per level coming down
  EXPECT_NEAR(found.translation().x(), dx, kStep);
  EXPECT_NEAR(std::atan2(found.linear()(1, 0), found.linear()(0, 0)), yaw, kTurn);
  // A grid that fits is searched as it is: the same pose as search_planar_motion, as many calls.
  calls = 0;
  const Pose small = search_planar_motion_bounded(initial, 4.0, kStep, 0.1, kTurn, 4000, score_for);
  EXPECT_EQ(calls.load(), planar_grid_size(4.0, kStep, 0.1, kTurn));
  EXPECT_TRUE(small.isApprox(search_planar_motion(initial, 4.0, kStep, 0.1, kTurn, score_for(kStep))));
}

TEST(Preregistration, ObjectsOfASegmentedSceneMatchThePerClusterClassification) {
  // extract_objects classifies from accumulated moments; the same clusters gathered and passed to
  // classify_object must give the same shapes.
  std::mt19937 rng(5);
  SegmentationResult seg;
  std::vector<Vec3> points;
  const std::vector<std::vector<Vec3>> objects = {
      pole({5, 2, -1.7}, kUp, 0.1, 3.0, rng), patch({10, -3, -1.7}, {0, 6, 0}, {0, 0, 3}, 0.01, rng),
      patch({3, 3, -1.7}, {4, 0, 0}, {0, 4, 0}, 0.01, rng), pole({-6, 4, -1.7}, kUp, 0.1, 4.0, rng)};
  for (std::size_t c = 0; c < objects.size(); ++c)
    for (const Vec3& p : objects[c]) {
      seg.image.point_of_pixel.push_back(static_cast<int>(points.size()));
      seg.pixel_label.push_back(static_cast<int>(c) + 1);
      points.push_back(p);
    }
  seg.num_clusters = static_cast<int>(objects.size());
  const PreRegistrationConfig cfg;
  const ObjectSet set = extract_objects(points, seg, cfg);
  int poles = 0, planes = 0;
  for (const auto& o : objects) {
    poles += classify_object(o, kUp, cfg) == ObjectShape::kPole;
    planes += classify_object(o, kUp, cfg) == ObjectShape::kPlane;
  }
  EXPECT_EQ(poles, 2);
  EXPECT_EQ(planes, 1);
  EXPECT_EQ(set.num_poles, poles);
  EXPECT_EQ(set.num_planes, planes);
  EXPECT_GT(set.poles.size(), 50u);
  EXPECT_GT(set.planes.size(), 50u);
}
