// Simulated LiDAR: ranges on known geometry within the noise, range limits and dropouts,
// rolling shutter (azimuth = firing time, moving objects seen where they are at that instant),
// mid-sweep ground-truth pose, and bit-for-bit determinism (also across TBB thread counts).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "dloam/core/range_image.hpp"
#include "dloam/sim/props.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"

using namespace dloam;
using namespace dloam::sim;

namespace {
// Flat world: ground (road) up to 9.9 m ahead, a wall whose face is the plane x = wall_x, and
// the ego at the origin heading +x at `speed`.
World wall_world(double wall_x, double speed) {
  World w;
  add_box_z(w.static_mesh, wall_x + 0.25, 0.0, 0.0, 0.5, 60.0, -5.0, 30.0, {cls::kBuilding, 0.5f});
  add_quad(w.static_mesh, Vec3(-60, -60, 0), Vec3(9.9, -60, 0), Vec3(9.9, 60, 0), Vec3(-60, 60, 0),
           {cls::kRoad, 0.2f});
  w.ego.path = Path::from_waypoints({{-100.0, 0.0}, {100.0, 0.0}}, 0.0, false);
  w.ego.s0 = 100.0;
  w.ego.profile = SpeedProfile::constant(speed);
  return w;
}

LidarOptions vlp16(double noise, double dropout) {
  LidarOptions o;
  o.sensor = sensor_preset("VLP-16");
  o.range_noise = noise;
  o.dropout = dropout;
  return o;
}

double circular_diff(double a, double b) { return std::abs(std::remainder(a - b, 1.0)); }
}  // namespace

TEST(SimLidar, RangesToAKnownWallAndGroundAreWithinTheNoise) {
  const double sigma = 0.02;
  Simulator sim(wall_world(10.0, 0.0), vlp16(sigma, 0.0));
  const SimFrame f = sim.frame(0);
  int wall = 0, ground = 0;
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < f.scan.cloud.size(); ++i) {
    const Vec3& p = f.scan.cloud.xyz[i];
    const Vec3 d = p.normalized();
    double expected;
    if (semantic::class_of(f.scan.labels[i]) == cls::kBuilding) {
      expected = 10.0 / d.x();
      ++wall;
    } else {
      ASSERT_EQ(semantic::class_of(f.scan.labels[i]), cls::kRoad);
      expected = -1.73 / d.z();
      ++ground;
    }
    const double res = p.norm() - expected;
    EXPECT_LT(std::abs(res), 5.0 * sigma) << p.transpose();
    sum += res;
    sum2 += res * res;
  }
  const int n = wall + ground;
  ASSERT_GT(wall, 1000);
  ASSERT_GT(ground, 1000);
  const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(stddev, sigma, 0.1 * sigma);
  // Without noise the geometry is exact up to float precision.
  Simulator exact(wall_world(10.0, 0.0), vlp16(0.0, 0.0));
  const SimFrame g = exact.frame(0);
  for (std::size_t i = 0; i < g.scan.cloud.size(); ++i)
    if (semantic::class_of(g.scan.labels[i]) == cls::kBuilding) {
      EXPECT_NEAR(g.scan.cloud.xyz[i].x(), 10.0, 2e-4);
    }
}

TEST(SimLidar, ReturnsBeyondMaxRangeAreAbsentAndDropoutsMatchTheirRate) {
  Simulator far(wall_world(150.0, 0.0), vlp16(0.02, 0.0));  // VLP-16 max range: 100 m
  for (Label l : far.frame(0).scan.labels) EXPECT_NE(semantic::class_of(l), cls::kBuilding);
  auto count = [](double dropout) {
    Simulator sim(wall_world(30.0, 0.0), vlp16(0.02, dropout));
    return static_cast<double>(sim.frame(0).scan.cloud.size());
  };
  const double all = count(0.0), kept = count(0.3);
  EXPECT_NEAR(kept / all, 0.7, 0.02);  // binomial sd ~ 0.003 at ~10k returns
}

TEST(SimLidar, AzimuthOfEveryPointIsItsFiringTime) {
  ScenarioParams p;
  p.frames = 10;
  p.ego_speed = 15.0;
  LidarOptions o = vlp16(0.02, 0.01);
  Simulator sim(make_world(p), o);
  const SimFrame f = sim.frame(4);
  const int cols = o.sensor.Horizon_SCAN;
  ASSERT_GT(f.scan.cloud.size(), 10000u);
  ASSERT_TRUE(f.scan.cloud.has_time() && f.scan.cloud.has_intensity());
  for (std::size_t i = 0; i < f.scan.cloud.size(); ++i) {
    const Vec3& q = f.scan.cloud.xyz[i];
    const double t = f.scan.cloud.time[i];
    EXPECT_LT(circular_diff(azimuth_time(q.x(), q.y()), t), 1.0 / cols);
    EXPECT_NEAR(t * cols - std::floor(t * cols), 0.5, 1e-3);  // column centre
    EXPECT_GE(f.scan.cloud.intensity[i], 0.0f);
    EXPECT_LE(f.scan.cloud.intensity[i], 1.0f);
    if (i > 0) {
      EXPECT_GE(t, f.scan.cloud.time[i - 1]);  // firing order
    }
  }
  EXPECT_TRUE(f.pose.isApprox(sim.sensor_pose(4, 0.5)));
  EXPECT_TRUE(sim.sensor_pose(4, 0.25).isApprox(sim.sensor_pose(0.425)));
  EXPECT_GT((sim.sensor_pose(4, 1.0).translation() - sim.sensor_pose(4, 0.0).translation()).norm(), 1.4);
}

TEST(SimLidar, AMovingTruckIsSeenWhereItIsWhenEachRayFires) {
  // A 10 m box-shaped truck overtakes a parked ego at 30 m/s, 4 m to its left: it spans a wide
  // azimuth, so its points are fired over ~25 ms while it moves ~0.75 m.
  World w = wall_world(80.0, 0.0);
  Actor truck;
  truck.kind = ActorKind::Truck;
  truck.instance = 5;
  add_box_z(truck.mesh, 0.0, 0.0, 0.0, 10.0, 2.5, 0.3, 3.5, {semantic::kUnlabeled, 0.5f});
  truck.dims = {10.0, 2.5, 3.5};
  truck.path = Path::from_waypoints({{-200.0, 4.0}, {200.0, 4.0}}, 0.0, false);
  truck.profile = SpeedProfile::constant(30.0);
  truck.s0 = 200.0 - 3.0 * 0.05;  // centre abeam of the sensor at mid-sweep (t = 0.05 s)
  w.actors.push_back(truck);
  Simulator sim(std::move(w), vlp16(0.0, 0.0));
  const SimFrame f = sim.frame(0);
  const Actor& a = sim.world().actors[0];
  int n = 0, outside_if_frozen = 0;
  double worst_if_frozen = 0.0;
  for (std::size_t i = 0; i < f.scan.cloud.size(); ++i) {
    if (semantic::instance_of(f.scan.labels[i]) != 5) continue;
    ++n;
    EXPECT_EQ(semantic::class_of(f.scan.labels[i]), semantic::kMovingOtherVehicle);
    const double t = f.scan.cloud.time[i] * 0.1;
    const Vec3 world = sim.sensor_pose(t) * f.scan.cloud.xyz[i];
    const Vec3 local = a.pose(sim.world().ground, t).inverse() * world;  // truck frame at firing time
    EXPECT_LT(std::abs(local.x()), 5.0 + 1e-3);
    EXPECT_LT(std::abs(local.y()), 1.25 + 1e-3);
    const Vec3 frozen = a.pose(sim.world().ground, 0.05).inverse() * world;  // truck frozen at mid-sweep
    outside_if_frozen += std::abs(frozen.x()) > 5.05;
    worst_if_frozen = std::max(worst_if_frozen, std::abs(frozen.x()) - 5.0);
  }
  ASSERT_GT(n, 2000);
  // Frozen at mid-sweep, the rear face (fired ~39 ms earlier) would be ~1.2 m off.
  EXPECT_GT(outside_if_frozen, 200);
  EXPECT_GT(worst_if_frozen, 0.8);
}

TEST(SimLidar, SameSeedGivesIdenticalScansWhateverTheThreadCount) {
  ScenarioParams p;
  p.frames = 6;
  p.seed = 11;
  auto run = [&](std::uint64_t noise_seed, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    LidarOptions o = vlp16(0.02, 0.01);
    o.seed = noise_seed;
    Simulator sim(make_world(p), o);
    return sim.frame(3).scan;
  };
  const Scan a = run(1, 2), b = run(1, 1), c = run(2, 2);
  ASSERT_GT(a.cloud.size(), 10000u);
  EXPECT_EQ(a.cloud.xyz, b.cloud.xyz);
  EXPECT_EQ(a.cloud.intensity, b.cloud.intensity);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_NE(a.cloud.xyz, c.cloud.xyz);  // other noise seed
}

TEST(SimLidar, BeamsFireFromTheirOwnOriginHeights) {
  // A calibrated sensor whose beams start at different heights (beam_vertical_offsets_m, as
  // fitted for KITTI's HDL-64E): every return lies on the wall or the ground exactly, and the
  // pipeline's beam lookup puts it back on the beam that fired it.
  LidarOptions o = vlp16(0.0, 0.0);
  o.sensor = sensor_preset("HDL-64E");
  o.sensor.beam_vertical_offsets_m.resize(static_cast<std::size_t>(o.sensor.N_scan));
  for (int r = 0; r < o.sensor.N_scan; ++r)  // lower block 0.12 m, upper block 0.20 m
    o.sensor.beam_vertical_offsets_m[static_cast<std::size_t>(r)] = r < 32 ? 0.12 : 0.2;
  Simulator sim(wall_world(10.0, 0.0), o);
  const SimFrame f = sim.frame(0);
  const BeamLookup beams(o.sensor);
  int wall = 0, ground = 0, same_row = 0;
  for (std::size_t i = 0; i < f.scan.cloud.size(); ++i) {
    const Vec3& p = f.scan.cloud.xyz[i];
    if (semantic::class_of(f.scan.labels[i]) == cls::kBuilding) {
      EXPECT_NEAR(p.x(), 10.0, 2e-4);
      ++wall;
    } else {
      EXPECT_NEAR(p.z(), -1.73, 2e-4);
      ++ground;
    }
    same_row += beams.row(p) == f.scan.rows[i];
  }
  ASSERT_GT(wall, 1000);
  ASSERT_GT(ground, 1000);
  EXPECT_EQ(same_row, wall + ground);
}
