// Scenes for map cleaning and hardening: the scripted pedestrians (standing then walking away,
// walking in then standing) and the parked car that drives off are labelled static, then moving,
// exactly in the scans where they stand and move; the tunnel and the open field lose the
// structure along the road that the city street has, and the street at the end brings it back.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <map>
#include <nanoflann.hpp>

#include "dloam/sim/props.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"

using namespace dloam;
using namespace dloam::sim;

namespace {
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Tree = nanoflann::KDTreeEigenMatrixAdaptor<Matrix>;

LidarOptions vlp16() {
  LidarOptions o;
  o.sensor = sensor_preset("VLP-16");
  return o;
}

// Per scan: points of an instance and how many of them are labelled moving.
struct Seen {
  int points = 0, moving = 0;
};

// Shares of the points of a scan whose local surface (PCA of the 10 nearest points within 1 m,
// world frame; `points` of them have such a surface) faces the driving direction
// (|normal . x| > 0.7) or is vertical (|normal . z| < 0.3), and of all points that stand more
// than 0.3 m above the ground (anything but road, sidewalk and terrain).
struct Structure {
  double facing_x = 0.0, vertical = 0.0, standing = 0.0;
  std::size_t points = 0;
};
Structure structure(const Simulator& sim, const SimFrame& f) {
  Matrix m(static_cast<Eigen::Index>(f.scan.cloud.size()), 3);
  for (std::size_t i = 0; i < f.scan.cloud.size(); ++i)
    m.row(static_cast<Eigen::Index>(i)) =
        (sim.sensor_pose(f.index, f.scan.cloud.time[i]) * f.scan.cloud.xyz[i]).transpose();
  Tree tree(3, std::cref(m), 10);
  constexpr std::size_t k = 10;
  Structure s;
  const Ground& g = sim.world().ground;
  for (Eigen::Index q = 0; q < m.rows(); ++q) s.standing += m(q, 2) - g.surface(m(q, 0), m(q, 1)) > 0.3;
  s.standing /= static_cast<double>(std::max<Eigen::Index>(m.rows(), 1));
  std::size_t facing = 0, vertical = 0;
  for (Eigen::Index q = 0; q < m.rows(); ++q) {
    Eigen::Index idx[k];
    double d2[k];
    const Vec3 p = m.row(q).transpose();
    if (tree.index->knnSearch(p.data(), k, idx, d2) < k || d2[k - 1] > 1.0) continue;
    Vec3 mean = Vec3::Zero();
    for (auto i : idx) mean += m.row(i).transpose();
    mean /= k;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (auto i : idx) cov += (m.row(i).transpose() - mean) * (m.row(i).transpose() - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / k);
    if (es.eigenvalues()(1) < 0.05 * 0.05) continue;  // neighbours on one ring: no surface
    const Vec3 n = es.eigenvectors().col(0);
    ++s.points;
    facing += std::abs(n.x()) > 0.7;
    vertical += std::abs(n.z()) < 0.3;
  }
  s.facing_x = static_cast<double>(facing) / static_cast<double>(std::max<std::size_t>(s.points, 1));
  s.vertical = static_cast<double>(vertical) / static_cast<double>(std::max<std::size_t>(s.points, 1));
  return s;
}
}  // namespace

TEST(SimSpecialScenes, ScriptedObjectsAreStaticThenMovingInTheScansWhereTheyStandAndMove) {
  ScenarioParams p;
  p.frames = 60;
  p.seed = 5;
  p.traffic = 0.5;
  p.cleaning_actors = true;
  p.leave_after = 20;
  Simulator sim(make_world(p), vlp16());
  const World& w = sim.world();
  std::map<std::string, const Actor*> role;
  for (const Actor& a : w.actors)
    if (!a.role.empty()) role[a.role] = &a;
  ASSERT_EQ(role.size(), 3u);
  const Actor& car = *role.at("leaving_car");
  // Its parking slot is free: no parked vehicle within 5 m of where it stands.
  const Vec2 slot = car.path.at(car.s0).p;
  for (const StaticObject& o : w.objects)
    if (o.instance != 0) {
      EXPECT_GT((o.position.head<2>() - slot).norm(), 5.0) << o.kind;
    }

  std::map<std::string, std::vector<Seen>> seen;
  for (int k = 0; k < p.frames; ++k) {
    const SimFrame f = sim.frame(k);
    for (const auto& [name, a] : role) {
      Seen s;
      for (std::size_t i = 0; i < f.scan.labels.size(); ++i) {
        const Label l = f.scan.labels[i];
        if (semantic::instance_of(l) != a->instance) continue;
        ++s.points;
        s.moving += semantic::is_moving(l);
        // Each point's label is the object's state at the point's firing time.
        EXPECT_EQ(semantic::is_moving(l),
                  a->speed((k + f.scan.cloud.time[i]) * w.frame_period) > kMovingSpeed);
      }
      seen[name].push_back(s);
    }
  }
  // Every point of the object in scans k0..k1-1 is static (moving); trees and poles may hide it
  // now and then, but it is seen in most of them.
  auto expect_state = [&](const std::string& name, int k0, int k1, bool moving) {
    int visible = 0;
    for (int k = k0; k < k1; ++k) {
      const Seen& s = seen[name][static_cast<std::size_t>(k)];
      visible += s.points > 0;
      EXPECT_EQ(s.moving, moving ? s.points : 0) << name << " scan " << k;
    }
    EXPECT_GE(visible, 0.8 * (k1 - k0)) << name << " scans " << k0 << "-" << k1;
  };
  // The car stands for exactly `leave_after` scans, then moves (2 m/s^2: past 0.2 m/s in 0.1 s).
  expect_state("leaving_car", 0, 20, false);
  expect_state("leaving_car", 21, 40, true);
  EXPECT_GT((car.pose(w.ground, 6.0).translation() - car.pose(w.ground, 0.0).translation()).norm(), 10.0);
  EXPECT_TRUE(car.pose(w.ground, 1.99).isApprox(car.pose(w.ground, 0.0)));
  // The pedestrians switch at half the drive (3 s, scan 30), at 1 m/s^2: one starts to walk at
  // 3.0 s and passes 0.2 m/s at 3.2 s; the other slows from 1.6 s and is under 0.2 m/s from 2.8 s.
  expect_state("stand_then_walk", 0, 32, false);
  expect_state("stand_then_walk", 32, 60, true);
  expect_state("walk_then_stand", 0, 28, true);
  expect_state("walk_then_stand", 28, 60, false);
}

TEST(SimSpecialScenes, TunnelAndOpenFieldLoseTheStructureAlongTheRoadAndTheStreetBringsItBack) {
  for (ScenarioKind kind : {ScenarioKind::Tunnel, ScenarioKind::OpenField}) {
    ScenarioParams p;
    p.kind = kind;
    p.frames = 600;  // 600 m: 60 m of street, 480 m of tunnel / field, 60 m of street
    p.seed = 2;
    p.traffic = 0.0;
    Simulator sim(make_world(p), vlp16());
    const Structure start = structure(sim, sim.frame(2));
    const SimFrame mid_frame = sim.frame(300);
    const Structure mid = structure(sim, mid_frame);
    const Structure end = structure(sim, sim.frame(595));
    const std::string name = to_string(kind);
    RecordProperty(name + "_facing_x_start_mid_end", std::to_string(start.facing_x) + " " +
                                                         std::to_string(mid.facing_x) + " " +
                                                         std::to_string(end.facing_x));
    RecordProperty(name + "_standing_start_mid_end", std::to_string(start.standing) + " " +
                                                         std::to_string(mid.standing) + " " +
                                                         std::to_string(end.standing));
    RecordProperty(name + "_vertical_start_mid_end", std::to_string(start.vertical) + " " +
                                                         std::to_string(mid.vertical) + " " +
                                                         std::to_string(end.vertical));
    EXPECT_GT(start.facing_x, 0.02) << name;
    EXPECT_GT(end.facing_x, 0.02) << name;
    if (kind == ScenarioKind::Tunnel) {
      // Walls and ceiling all around and nothing facing the driving direction (the lamps are too
      // small for a surface), many vertical points, and points above the sensor.
      ASSERT_GT(mid.points, 1000u) << name;
      EXPECT_LT(mid.facing_x, 0.005) << name;
      EXPECT_LT(mid.facing_x, 0.2 * std::min(start.facing_x, end.facing_x)) << name;
      EXPECT_GT(mid.vertical, 0.3) << name;
      int above = 0;
      for (const Vec3& q : mid_frame.scan.cloud.xyz) above += q.z() > 3.0;
      EXPECT_GT(above, static_cast<int>(mid_frame.scan.cloud.size() / 20)) << name;
    } else {
      // Flat ground and hardly anything standing on it (sparse rings on flat ground give no
      // PCA surfaces, hence the height above the ground).
      EXPECT_LT(mid.standing, 0.01) << name;
      EXPECT_GT(start.standing, 0.2) << name;
      EXPECT_GT(end.standing, 0.2) << name;
      int road_or_terrain = 0;
      for (Label l : mid_frame.scan.labels)
        road_or_terrain += semantic::class_of(l) == cls::kRoad || semantic::class_of(l) == cls::kTerrain;
      EXPECT_GT(road_or_terrain, static_cast<int>(0.97 * static_cast<double>(mid_frame.scan.labels.size())))
          << name;
    }
  }
}
