// Simulator motion model: line + arc paths, speed profiles, stop-and-go actors, actor labels,
// scenario worlds (loop closes on itself, highway speeds, reproducible generation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dloam/sim/city.hpp"
#include "dloam/sim/scenario.hpp"

using namespace dloam;
using namespace dloam::sim;

TEST(SimPath, LinesAndArcsAreContinuousAndArcLengthParametrised) {
  const Path p = Path::from_waypoints({{0, 0}, {50, 0}, {50, 30}, {0, 30}}, 8.0, true);
  // Perimeter 160 m minus, at each of the 4 corners, 2 r - r pi / 2.
  EXPECT_NEAR(p.length(), 160.0 - 4.0 * (2.0 * 8.0 - 8.0 * M_PI / 2.0), 1e-9);
  double prev_yaw = p.at(0.0).yaw;
  for (double s = 0.01; s < p.length(); s += 0.01) {
    const PathPoint a = p.at(s - 0.01), b = p.at(s);
    EXPECT_NEAR((b.p - a.p).norm(), 0.01, 1e-6) << s;
    EXPECT_LT(std::abs(std::remainder(b.yaw - prev_yaw, 2.0 * M_PI)), 0.01 / 8.0 + 1e-9) << s;
    prev_yaw = b.yaw;
  }
  EXPECT_NEAR((p.at(p.length()).p - p.at(0.0).p).norm(), 0.0, 1e-9);  // closed
  EXPECT_NEAR((p.at(p.length() + 3.0).p - p.at(3.0).p).norm(), 0.0, 1e-9);
}

TEST(SimPath, OffsetAndReversedCurvesAreParallelAndOpposite) {
  const Path p = Path::from_waypoints({{0, 0}, {100, 0}, {160, 60}, {160, 200}}, 20.0, false);
  const Path right = p.offset(-3.0), back = p.reversed();
  EXPECT_NEAR(back.length(), p.length(), 1e-9);
  for (double s = 0.0; s <= p.length(); s += 1.0) {
    const PathPoint a = p.at(s), r = back.at(p.length() - s);
    EXPECT_NEAR((a.p - r.p).norm(), 0.0, 1e-6);
    EXPECT_NEAR(std::abs(std::remainder(a.yaw - r.yaw, 2.0 * M_PI)), M_PI, 1e-6);
  }
  // Every point of the offset curve is 3 m from the original curve (dense search).
  for (double s = 0.0; s <= right.length(); s += 2.5) {
    double best = 1e9;
    for (double u = 0.0; u <= p.length(); u += 0.01)
      best = std::min(best, (p.at(u).p - right.at(s).p).norm());
    EXPECT_NEAR(best, 3.0, 1e-3) << s;
  }
  EXPECT_THROW(Path::from_waypoints({{1, 1}}, 1.0, false), std::invalid_argument);
}

TEST(SimPath, SpeedProfileIntegratesItsSpeed) {
  const SpeedProfile prof({{-1.0, 2.0}, {1.0, 2.0}, {2.0, 0.0}, {5.0, 0.0}, {6.5, 3.0}});
  EXPECT_DOUBLE_EQ(prof.distance(0.0), 0.0);
  double numeric = 0.0;
  const double dt = 1e-4;
  for (double t = 0.0; t < 8.0 - 1e-9; t += dt) numeric += prof.speed(t + 0.5 * dt) * dt;
  EXPECT_NEAR(prof.distance(8.0), numeric, 1e-6);
  EXPECT_NEAR(prof.distance(-1.0), -2.0, 1e-12);
  EXPECT_DOUBLE_EQ(prof.speed(3.0), 0.0);
  EXPECT_DOUBLE_EQ(prof.speed(10.0), 3.0);
  EXPECT_THROW(SpeedProfile({{1.0, 1.0}, {0.0, 1.0}}), std::invalid_argument);
  EXPECT_THROW(SpeedProfile({{0.0, -1.0}}), std::invalid_argument);
}

TEST(SimActors, StopAndGoAlternatesAndLabelsFollowTheSpeed) {
  Rng rng(3);
  const SpeedProfile prof = stop_and_go_profile(rng, 1.4, -2.0, 60.0, {}, false);
  Actor a;
  a.kind = ActorKind::Pedestrian;
  a.instance = 77;
  a.path = Path::from_waypoints({{0, 0}, {100, 0}}, 0.0, false);
  a.profile = prof;
  int moving = 0, standing = 0, switches = 0;
  bool last = a.moving(0.0);
  for (double t = 0.0; t < 60.0; t += 0.05) {
    const bool m = a.moving(t);
    switches += m != last;
    last = m;
    (m ? moving : standing)++;
    const Label l = a.label(t);
    EXPECT_EQ(semantic::instance_of(l), 77u);
    EXPECT_EQ(semantic::class_of(l), m ? semantic::kMovingPerson : semantic::kPerson);
    EXPECT_EQ(m, a.speed(t) > 0.2);
  }
  EXPECT_GT(moving, 100);
  EXPECT_GT(standing, 100);
  EXPECT_GE(switches, 4);
  // The distance never decreases and grows only while moving.
  EXPECT_LE(prof.distance(10.0), prof.distance(10.5));
}

TEST(SimScenario, LoopReturnsToItsStartAndNeedsAbout1100FramesPerKm) {
  ScenarioParams p;
  p.kind = ScenarioKind::Loop;
  p.frames = 1100;
  p.traffic = 0.3;
  const World w = make_world(p);
  ASSERT_TRUE(w.ego.path.closed());
  const double lap = w.ego.path.length();
  const double drive = p.speed() * p.frames * w.frame_period;
  EXPECT_NEAR(lap / drive, 1.0, 0.25);
  const double t_lap = lap / p.speed();
  EXPECT_LT((w.ego.position(t_lap) - w.ego.position(0.0)).norm(), 1e-6);
  EXPECT_GT((w.ego.position(0.5 * t_lap) - w.ego.position(0.0)).norm(), 50.0);
  // 1 km at the default loop speed takes 1000-1500 frames.
  const double frames_per_km = 1000.0 / p.speed() / w.frame_period;
  EXPECT_GE(frames_per_km, 1000.0);
  EXPECT_LE(frames_per_km, 1500.0);
}

TEST(SimScenario, HighwayTrafficIsFastAndBothWays) {
  ScenarioParams p;
  p.kind = ScenarioKind::Highway;
  p.frames = 100;
  const World w = make_world(p);
  ASSERT_GT(w.actors.size(), 20u);
  int oncoming = 0;
  for (const Actor& a : w.actors) {
    EXPECT_GE(a.speed(3.0), 20.0);
    EXPECT_LE(a.speed(3.0), 35.0);
    EXPECT_TRUE(a.kind == ActorKind::Car || a.kind == ActorKind::Truck);
    const double heading = a.pose(w.ground, 3.0)
                               .linear()
                               .col(0)
                               .head<2>()
                               .dot(w.ego.sensor_pose(w.ground, 3.0).linear().col(0).head<2>());
    oncoming += heading < 0.0;
  }
  EXPECT_GT(oncoming, 5);
  EXPECT_LT(oncoming, static_cast<int>(w.actors.size()) - 5);
}

TEST(SimScenario, SameSeedSameWorldOtherSeedOtherWorld) {
  ScenarioParams p;
  p.frames = 30;
  const World a = make_world(p), b = make_world(p);
  p.seed = 2;
  const World c = make_world(p);
  ASSERT_EQ(a.static_mesh.vertices.size(), b.static_mesh.vertices.size());
  EXPECT_TRUE(std::equal(a.static_mesh.vertices.begin(), a.static_mesh.vertices.end(),
                         b.static_mesh.vertices.begin()));
  ASSERT_EQ(a.actors.size(), b.actors.size());
  for (std::size_t i = 0; i < a.actors.size(); ++i)
    EXPECT_TRUE(a.actors[i].pose(a.ground, 1.0).isApprox(b.actors[i].pose(b.ground, 1.0)));
  EXPECT_FALSE(a.static_mesh.vertices.size() == c.static_mesh.vertices.size() &&
               std::equal(a.static_mesh.vertices.begin(), a.static_mesh.vertices.end(),
                          c.static_mesh.vertices.begin()));
  EXPECT_THROW(parse_scenario_kind("desert"), std::invalid_argument);
  p.frames = 0;
  EXPECT_THROW(make_world(p), std::invalid_argument);
}

TEST(SimScenario, TrafficAndDensityScaleTheScene) {
  for (ScenarioKind kind : {ScenarioKind::Urban, ScenarioKind::Highway, ScenarioKind::Loop}) {
    ScenarioParams p;
    p.kind = kind;
    p.frames = 50;
    p.traffic = 0.0;
    EXPECT_TRUE(make_world(p).actors.empty()) << to_string(kind);
    p.traffic = 1.0;
    const World normal = make_world(p);
    p.traffic = 3.0;
    EXPECT_GT(make_world(p).actors.size(), 2 * normal.actors.size()) << to_string(kind);
    p.density = 3.0;
    EXPECT_GT(make_world(p).static_mesh.size(), normal.static_mesh.size()) << to_string(kind);
  }
}

TEST(SimScenario, HeavyCityTrafficQueuesAheadOfAndBehindTheEgoWithoutTouchingAnything) {
  ScenarioParams p;
  p.frames = 100;
  p.traffic = 3.0;
  const World w = make_world(p);
  const double duration = p.frames * w.frame_period;
  int ahead = 0, behind = 0;
  for (const Actor& a : w.actors) {
    if (a.kind != ActorKind::Car && a.kind != ActorKind::Truck) continue;
    const Vec2 rel = a.path.at(a.s0).p - w.ego.position(0.0);
    const bool in_lane = std::abs(rel.y()) < 0.05 && a.path.at(a.s0).yaw == w.ego.path.at(w.ego.s0).yaw;
    if (!in_lane || std::abs(a.speed(0.0) - w.ego.profile.speed(0.0)) > 0.4) continue;
    (rel.x() > 0.0 ? ahead : behind) += 1;
    // The queue never closes on the ego, and nothing else drives or walks through it.
    for (double t = 0.0; t <= duration; t += 0.1) {
      const Vec2 q = a.path.at(a.s0 + a.profile.distance(t)).p;
      EXPECT_GT((q - w.ego.position(t)).norm(), 3.5) << t;
      for (const Actor& o : w.actors) {
        if (&o == &a || !o.present(t)) continue;
        const Vec2 d = o.path.at(o.s0 + o.profile.distance(t)).p - q;
        const double reach = 0.5 * std::max(o.dims.length, o.dims.width);
        EXPECT_FALSE(std::abs(d.x()) < 0.5 * a.dims.length + reach &&
                     std::abs(d.y()) < 0.5 * a.dims.width + reach)
            << "actor " << o.instance << " overlaps queue vehicle " << a.instance << " at t = " << t;
      }
    }
  }
  EXPECT_GE(ahead, 1);
  EXPECT_GE(behind, 1);
}

TEST(SimScenario, NoQueueAtTheDefaultTraffic) {
  ScenarioParams p;
  p.frames = 100;
  World w = make_world(p);
  const std::size_t n = w.actors.size();
  Rng rng(7);
  add_ego_flow(w, rng, 1.0, sample_route(w.ego, 10.0, {}, 120.0));
  EXPECT_EQ(w.actors.size(), n);
  add_ego_flow(w, rng, 3.0, sample_route(w.ego, 10.0, {}, 120.0));
  EXPECT_GT(w.actors.size(), n);
}
