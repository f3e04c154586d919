// Loop closure: the Ceres pose graph on a square loop with drifting odometry, loop detection and
// verification on a synthetic town revisited with a known drift, rejection of places that only
// look close, and the Mapper's loop integration (corrected keyframes, corrected trajectory).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dloam/core/loop_closure.hpp"
#include "dloam/core/mapping.hpp"
#include "dloam/core/pose_graph.hpp"
#include "pose_test_util.hpp"

using namespace dloam;

namespace {

using test::make_pose;

/// Pose at arc length s on a square of side `side` driven counter-clockwise from the origin along +x.
Pose square_pose(double s, double side) {
  const double perimeter = 4 * side;
  s = std::fmod(s, perimeter);
  const int leg = static_cast<int>(s / side);
  const double u = s - leg * side;
  const Vec3 corners[] = {{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}};
  const Vec3 dirs[] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  return make_pose(leg * M_PI / 2, corners[leg] + u * dirs[leg]);
}

/// A town: ground, random building faces and poles around a 40 m square street loop (world frame).
struct Town {
  std::vector<Vec3> edges, planes;
};

Town make_town(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  Town t;
  for (double x = -20; x <= 60; x += 0.6)
    for (double y = -20; y <= 60; y += 0.6)
      t.planes.emplace_back(x + 0.2 * u(rng), y + 0.2 * u(rng), -1.8 + noise(rng));
  for (int b = 0; b < 40; ++b) {  // building faces: random length, orientation, offset from the street
    const double s = 160.0 * u(rng);
    const Pose street = square_pose(s, 40.0);
    const double side = u(rng) < 0.5 ? -1.0 : 1.0;
    const Vec3 c = street * Vec3(0, side * (7 + 6 * u(rng)), 0);
    const double yaw = 2 * M_PI * u(rng), len = 4 + 8 * u(rng);
    const Vec3 d(std::cos(yaw), std::sin(yaw), 0);
    for (double a = -len / 2; a <= len / 2; a += 0.25)
      for (double z = -1.6; z <= 3.0; z += 0.3)
        t.planes.push_back(c + a * d + Vec3(noise(rng), noise(rng), z));
    for (double z = -1.6; z <= 3.0; z += 0.1) t.edges.push_back(c + len / 2 * d + Vec3(0, 0, z));  // corner
  }
  for (int p = 0; p < 60; ++p) {  // poles
    const Vec3 c = square_pose(160.0 * u(rng), 40.0) * Vec3(0, (u(rng) < 0.5 ? -1 : 1) * (4 + 3 * u(rng)), 0);
    for (double z = -1.8; z <= 2.5; z += 0.1) t.edges.push_back(c + Vec3(noise(rng), noise(rng), z));
  }
  return t;
}

/// A keyframe seeing the town within 20 m of its true pose, stored at `estimate`.
Keyframe observe(const Town& town, std::size_t scan, const Pose& truth, const Pose& estimate) {
  Keyframe kf;
  kf.scan = scan;
  kf.pose = estimate;
  const Pose inv = truth.inverse();
  for (const Vec3& p : town.edges)
    if ((p - truth.translation()).head<2>().norm() < 20) kf.edges.push_back(inv * p);
  for (const Vec3& p : town.planes)
    if ((p - truth.translation()).head<2>().norm() < 20) kf.planes.push_back(inv * p);
  return kf;
}

/// Keyframe i of a drive around the square, 2 m apart and 1 s apart (10 Hz), second lap shifted by 0.9 m.
Pose drive_truth(std::size_t i) { return square_pose(i < 80 ? 2.0 * i : 2.0 * i - 160 + 0.9, 40.0); }

/// Drift after keyframe 14: a yaw and translation error growing with the keyframe index.
Pose drift(std::size_t i) {
  const double k = i > 14 ? static_cast<double>(i - 14) : 0.0;
  return make_pose(0.001 * k, Vec3(0.03 * k, -0.02 * k, 0.0));
}

double position_error(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }

}  // namespace

TEST(PoseGraph, LoopEdgeRemovesInjectedDrift) {
  // 40 steps of 1 m around a 10 m square: node 40 is back at node 0.
  std::vector<Pose> truth;
  for (int i = 0; i <= 40; ++i) truth.push_back(square_pose(i, 10.0));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<PoseGraphEdge> edges;
  std::vector<Pose> chained{truth[0]};
  for (int i = 0; i < 40; ++i) {
    const Pose z =
        truth[i].inverse() * truth[i + 1] * make_pose(0.01 + noise(rng), Vec3(0.03, 0.01, noise(rng)));
    edges.push_back(
        {static_cast<std::size_t>(i), static_cast<std::size_t>(i + 1), z, Mat6::Identity(), false});
    chained.push_back(chained.back() * z);
  }
  const double before = position_error(chained.back(), truth.back());
  ASSERT_GT(before, 1.0);  // the drift is real

  // Without the loop the odometry chain is already optimal: nothing moves.
  const auto open = optimize_pose_graph(chained, edges);
  EXPECT_LT(position_error(open.back(), chained.back()), 1e-6);

  edges.push_back({0, 40, truth[0].inverse() * truth[40], information_from_sigmas(0.01, 0.01), true});
  PoseGraphSummary summary;
  const auto closed = optimize_pose_graph(chained, edges, {}, &summary);
  const double after = position_error(closed.back(), truth.back());
  std::printf("pose graph: end-point error %.3f m -> %.4f m, cost %.3g -> %.3g\n", before, after,
              summary.initial_cost, summary.final_cost);
  EXPECT_TRUE(summary.usable);
  EXPECT_LT(after, before / 10);
  EXPECT_TRUE(closed.front().isApprox(truth.front(), 1e-12));  // first pose fixed
  double worst_before = 0, worst_after = 0;
  for (int i = 0; i <= 40; ++i) {
    worst_before = std::max(worst_before, position_error(chained[i], truth[i]));
    worst_after = std::max(worst_after, position_error(closed[i], truth[i]));
  }
  EXPECT_LT(worst_after, worst_before / 2);
  // Deterministic.
  const auto again = optimize_pose_graph(chained, edges);
  for (int i = 0; i <= 40; ++i) ASSERT_TRUE(again[i].matrix() == closed[i].matrix()) << i;
}

TEST(PoseGraph, RejectsEdgesToMissingNodes) {
  const std::vector<Pose> poses(3, Pose::Identity());
  EXPECT_THROW(optimize_pose_graph(poses, {{0, 3, Pose::Identity(), Mat6::Identity(), false}}),
               std::invalid_argument);
}

TEST(LoopClosure, FindsTheRevisitAndRecoversTheDrift) {
  const Town town = make_town(11);
  std::vector<Keyframe> kfs;
  for (std::size_t i = 0; i <= 82; ++i)
    kfs.push_back(observe(town, 10 * i, drive_truth(i), drift(i) * drive_truth(i)));
  LoopParams params;  // 7 m, 30 s at 10 Hz = 30 keyframes here
  // No candidate before the drive comes back near the start (the last side's estimates drift into the
  // radius).
  for (std::size_t i = 1; i <= 70; ++i) ASSERT_FALSE(find_loop_candidate(kfs, i, params)) << i;

  const std::size_t cur = 82;
  ASSERT_GT(position_error(kfs[cur].pose, drive_truth(cur)), 1.5);  // drifted by metres
  const auto loop = detect_loop(kfs, cur, params);
  ASSERT_TRUE(loop);
  EXPECT_EQ(loop->current, cur);
  EXPECT_LE(loop->candidate, 14u);  // near the start, in the drift-free part
  EXPECT_LT(position_error(drive_truth(loop->candidate), drive_truth(cur)), params.search_radius);
  const Pose expected = drive_truth(loop->candidate).inverse() * drive_truth(cur);
  const Pose err = expected.inverse() * loop->relative;
  std::printf("loop %zu -> %zu: fitness %.3f m, %d matches, error %.3f m %.3f deg\n", loop->candidate,
              loop->current, loop->fitness, loop->matches, err.translation().norm(),
              rotation_angle(err) * 180 / M_PI);
  EXPECT_LT(err.translation().norm(), 0.05);
  EXPECT_LT(rotation_angle(err), 0.2 * M_PI / 180);
  EXPECT_LT(loop->fitness, params.max_fitness);
}

TEST(LoopClosure, NoFalseLoopWithoutRevisit) {
  const Town town = make_town(11);
  const Town elsewhere = make_town(12);  // another town: same street layout, other buildings and poles
  std::vector<Keyframe> kfs;
  for (std::size_t i = 0; i < 80; ++i) kfs.push_back(observe(town, 10 * i, drive_truth(i), drive_truth(i)));
  LoopParams params;
  // A drive that does not come back: no candidate at all.
  for (std::size_t i = 1; i < 20; ++i) ASSERT_FALSE(find_loop_candidate(kfs, i, params));
  // A keyframe estimated near the start, seeing other geometry: a candidate, rejected by verification.
  kfs.push_back(observe(elsewhere, 800, drive_truth(81), drive_truth(81)));
  const auto candidate = find_loop_candidate(kfs, 80, params);
  ASSERT_TRUE(candidate);
  EXPECT_FALSE(verify_loop(kfs, 80, *candidate, params));
}

TEST(LoopClosure, MapperClosesTheLoopAndCorrectsItsTrajectory) {
  const Town town = make_town(11);
  MappingConfig config;
  config.keyframe_distance = 1.5;  // every 2 m scan below is a keyframe
  const auto run = [&](bool loop_closure, std::vector<Pose>& reported) {
    config.loop_closure = loop_closure;
    std::mt19937 rng(5);  // the same predictions in both runs
    std::normal_distribution<double> noise(0.0, 0.05);
    Mapper mapper(config, 10.0);
    std::size_t first_loop = 0;
    for (std::size_t i = 0; i <= 84; ++i) {
      const Keyframe view = observe(town, 0, drive_truth(i), Pose::Identity());
      const Pose predicted = drive_truth(i) * make_pose(0.2 * noise(rng), Vec3(noise(rng), noise(rng), 0));
      const MappingResult m = mapper.process(10 * i, {view.edges, view.planes, {}, {}}, predicted);
      EXPECT_TRUE(m.keyframe) << i;
      if (m.loop && first_loop == 0) first_loop = i;
      reported.push_back(m.pose);
    }
    mapper.finish();
    // Scan 10 i is keyframe i; scans 10 i + 1..9 (never mapped) are reported at keyframe i's pose.
    std::vector<Pose> scan_poses;
    for (std::size_t s = 0; s <= 840; ++s) scan_poses.push_back(reported[s / 10]);
    const auto corrected = mapper.corrected_trajectory(scan_poses);
    EXPECT_EQ(mapper.keyframes().size(), 85u);
    double worst = 0.0;
    for (std::size_t s = 0; s < corrected.size(); ++s) {
      EXPECT_TRUE(corrected[s].isApprox(mapper.keyframes()[s / 10].pose, 1e-9)) << s;
      worst = std::max(worst, position_error(corrected[s], drive_truth(s / 10)));
    }
    std::printf("mapper (loop closure %s): worst keyframe error %.3f m\n", loop_closure ? "on" : "off",
                worst);
    EXPECT_LT(worst, 0.3);
    return std::make_tuple(first_loop, mapper.loops().size(), worst);
  };
  std::vector<Pose> with, without;
  const auto [first_loop, loops, worst_with] = run(true, with);
  std::printf("mapper: %zu loops, first at keyframe %zu\n", loops, first_loop);
  EXPECT_GE(first_loop, 70u);  // back within the search radius of the start (keyframe 80 is at it)
  EXPECT_GE(loops, 1u);
  const auto [no_loop, no_loops, worst_without] = run(false, without);
  EXPECT_EQ(no_loops, 0u);
  EXPECT_EQ(no_loop, 0u);
  EXPECT_LT(worst_with, worst_without + 0.02);  // closing a consistent loop does not hurt
  // Loop closure off: the same poses, bit for bit, until the first loop.
  for (std::size_t i = 0; i < first_loop; ++i) ASSERT_TRUE(with[i].matrix() == without[i].matrix()) << i;
}

TEST(LoopClosure, MapperCorrectsTiltFarFromTheOrigin) {
  // The town 900 m from the world origin: a rotation about the origin is there almost a translation,
  // so a registration linearised about the origin is ill-conditioned and its degeneracy test froze
  // z (and with it roll and pitch). About the sensor, a tilted prediction is corrected as near the origin.
  const Pose far = make_pose(0.4, Vec3(700.0, -560.0, 25.0));
  Town town = make_town(11);
  for (Vec3& p : town.edges) p = far * p;
  for (Vec3& p : town.planes) p = far * p;
  const auto truth = [&](std::size_t i) { return far * drive_truth(i); };
  MappingConfig config;
  config.loop_closure = false;
  config.keyframe_distance = 1.5;
  Mapper mapper(config, 10.0);
  for (std::size_t i = 0; i < 5; ++i) {  // keyframes at their true poses
    const Keyframe view = observe(town, 0, truth(i), Pose::Identity());
    mapper.process(i, {view.edges, view.planes, {}, {}}, truth(i));
  }
  Pose tilt = Pose::Identity();
  tilt.rotate(Eigen::AngleAxisd(0.5 * M_PI / 180, Vec3::UnitX()));
  tilt.rotate(Eigen::AngleAxisd(-0.4 * M_PI / 180, Vec3::UnitY()));
  tilt.translation() = Vec3(0.05, -0.05, 0.15);
  const Keyframe view = observe(town, 0, truth(5), Pose::Identity());
  const MappingResult m = mapper.process(5, {view.edges, view.planes, {}, {}}, truth(5) * tilt);
  const Pose err = truth(5).inverse() * m.pose;
  std::printf("far from the origin: tilt %.3f deg, %.3f m -> %.4f deg, %.4f m\n",
              rotation_angle(tilt) * 180 / M_PI, tilt.translation().norm(), rotation_angle(err) * 180 / M_PI,
              err.translation().norm());
  EXPECT_FALSE(m.registration.degenerate());
  EXPECT_LT(rotation_angle(err), 0.05 * M_PI / 180);
  EXPECT_LT(err.translation().norm(), 0.02);
}

TEST(LoopClosure, ALoopRunsBesideTheScansAndIsTakenAtAFixedScan) {
  const Town town = make_town(11);
  MappingConfig config;
  config.keyframe_distance = 1.5;  // every scan below is a keyframe
  config.loop_min_time_s = 3.0;    // scans 0.1 s apart
  struct Run {
    std::vector<Pose> reported;
    std::vector<std::size_t> loops_at;  // scans that took a loop
    std::vector<Pose> keyframes, corrected;
  };
  const auto run = [&](bool loop_closure, double latency_s, double interval_s = 0.0) {
    config.loop_closure = loop_closure;
    config.loop_latency_s = latency_s;
    config.loop_min_interval_s = interval_s;
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.05);
    Mapper mapper(config, 10.0);
    Run r;
    for (std::size_t i = 0; i <= 84; ++i) {
      const Keyframe view = observe(town, 0, drive_truth(i), Pose::Identity());
      const Pose predicted = drive_truth(i) * make_pose(0.2 * noise(rng), Vec3(noise(rng), noise(rng), 0));
      const MappingResult m = mapper.process(i, {view.edges, view.planes, {}, {}}, predicted);
      EXPECT_TRUE(m.keyframe) << i;
      if (m.loop) r.loops_at.push_back(i);
      r.reported.push_back(m.pose);
    }
    mapper.finish();
    for (const Keyframe& kf : mapper.keyframes()) r.keyframes.push_back(kf.pose);
    r.corrected = mapper.corrected_trajectory(r.reported);
    return r;
  };
  const Run at_once = run(true, 0.0), beside = run(true, 0.5), again = run(true, 0.5), off = run(false, 0.5);
  ASSERT_FALSE(at_once.loops_at.empty());
  ASSERT_FALSE(beside.loops_at.empty());
  EXPECT_TRUE(off.loops_at.empty());
  std::printf("loops taken at once at scans %zu.., beside the scans at %zu.. (%zu and %zu loops)\n",
              at_once.loops_at.front(), beside.loops_at.front(), at_once.loops_at.size(),
              beside.loops_at.size());
  // The first loop is found on the same keyframe and taken 0.5 s = 5 scans later; one job at a
  // time, so the next is found no earlier than that.
  EXPECT_EQ(beside.loops_at.front(), at_once.loops_at.front() + 5);
  for (std::size_t j = 1; j < beside.loops_at.size(); ++j)
    EXPECT_GE(beside.loops_at[j], beside.loops_at[j - 1] + 5);
  // Until a loop is taken nothing of it shows: the poses are those of a run without loop closure.
  for (std::size_t i = 0; i < beside.loops_at.front(); ++i)
    ASSERT_TRUE(beside.reported[i].matrix() == off.reported[i].matrix()) << i;
  // The scan that takes it (and every later one) is reported in the corrected map.
  double worst = 0.0;
  for (std::size_t i = 0; i < beside.keyframes.size(); ++i) {
    worst = std::max(worst, position_error(beside.keyframes[i], drive_truth(i)));
    // Every scan is a keyframe: its corrected pose is the keyframe's current one.
    EXPECT_TRUE(beside.corrected[i].isApprox(beside.keyframes[i], 1e-9)) << i;
  }
  EXPECT_LT(worst, 0.3);
  // Thread timing does not show: a second run gives the same poses, bit for bit.
  ASSERT_EQ(again.loops_at, beside.loops_at);
  for (std::size_t i = 0; i < beside.reported.size(); ++i)
    ASSERT_TRUE(again.reported[i].matrix() == beside.reported[i].matrix()) << i;
  for (std::size_t i = 0; i < beside.keyframes.size(); ++i)
    ASSERT_TRUE(again.keyframes[i].matrix() == beside.keyframes[i].matrix()) << i;

  // loop_min_interval_s: after a loop is taken, none is searched for that long (0.3 s = 3 scans).
  const Run spaced = run(true, 0.0, 0.3);
  ASSERT_GE(at_once.loops_at.size(), 4u);  // at once, the revisit closes a loop at every keyframe
  ASSERT_GE(spaced.loops_at.size(), 2u);
  EXPECT_LT(spaced.loops_at.size(), at_once.loops_at.size());
  EXPECT_EQ(spaced.loops_at.front(), at_once.loops_at.front());
  for (std::size_t j = 1; j < spaced.loops_at.size(); ++j)
    EXPECT_GE(spaced.loops_at[j], spaced.loops_at[j - 1] + 3);
}
