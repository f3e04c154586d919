// Highway scenario (paper Scenario 2): a gently curving 3+3-lane motorway; every lane carries a
// stream of cars and trucks at one speed between 20 and 35 m/s, placed so that they pass the ego
// during the drive (overtaking, being overtaken, oncoming). Sparse structure: guard rails,
// fences, noise walls, lamp and sign poles, scattered trees and farm buildings.
#include <algorithm>
#include <cmath>

#include "dloam/sim/city.hpp"
#include "dloam/sim/props.hpp"
#include "dloam/sim/scenario.hpp"

namespace dloam::sim::detail {

namespace {
constexpr double kLaneWidth = 3.6;
constexpr double kMedian = 2.0;     // half width of the median
constexpr double kShoulder = 13.6;  // half width of the paved road
constexpr double kVerge = 100.0;    // terrain on each side

double lane_offset(int lane) { return -(kMedian + kLaneWidth * (lane + 0.5)); }  // lane 0 = fast lane

Vec2 at_offset(const Path& p, double s, double d) {
  const PathPoint pp = p.at(s);
  return pp.p + d * Vec2(-std::sin(pp.yaw), std::cos(pp.yaw));
}

void build_structure(World& w, const Path& road, Rng& rng, double density) {
  const double L = road.length();
  add_ground_ribbon(w.static_mesh, w.ground, road, 0.0, L, -kShoulder, kShoulder, 4.0, {cls::kRoad, 0.22f});
  for (double side : {-1.0, 1.0}) {
    add_ground_ribbon(w.static_mesh, w.ground, road, 0.0, L, side * kShoulder, side * kVerge, 6.0,
                      {cls::kTerrain, 0.3f});
    add_guard_rail(w.static_mesh, w.ground, road, 0.0, L, side * (kShoulder - 0.2));
    add_guard_rail(w.static_mesh, w.ground, road, 0.0, L, side * 0.6);
  }
  for (double s = 0.0; s < L; s += 100.0) {
    for (double side : {-1.0, 1.0}) {
      if (chance(rng, 0.6)) {  // fence
        const double d = side * uniform(rng, 25.0, 38.0);
        add_fence(w.static_mesh, w.ground, at_offset(road, s, d), at_offset(road, s + 50.0, d),
                  uniform(rng, 1.2, 2.0));
        add_fence(w.static_mesh, w.ground, at_offset(road, s + 50.0, d), at_offset(road, s + 100.0, d),
                  uniform(rng, 1.2, 2.0));
      }
      if (chance(rng, 0.12 * density)) {  // noise wall
        const double d = side * 16.5, h = uniform(rng, 2.5, 4.0);
        for (double u = s; u < s + 100.0; u += 10.0)
          add_wall(w.static_mesh, w.ground, at_offset(road, u, d), at_offset(road, u + 10.0, d), h, 0.25);
      }
      const int trees = static_cast<int>(std::lround(uniform(rng, 0.0, 3.0) * density));
      for (int k = 0; k < trees; ++k) {
        const double u = s + uniform(rng, 0.0, 100.0);
        const Vec2 at = at_offset(road, u, side * uniform(rng, 17.0, 60.0));
        add_tree(w.static_mesh, rng, w.ground, at, uniform(rng, 5.0, 14.0));
        w.objects.push_back({"tree", 0, Vec3(at.x(), at.y(), 0.0), 0.0, {4.0, 4.0, 10.0}});
      }
      if (chance(rng, 0.25 * density)) {  // farm building
        const double u = s + uniform(rng, 10.0, 90.0);
        const PathPoint pp = road.at(u);
        const Vec2 front = at_offset(road, u, side * uniform(rng, 50.0, 80.0));
        const double width = uniform(rng, 10.0, 25.0), depth = uniform(rng, 8.0, 15.0),
                     h = uniform(rng, 4.0, 9.0);
        add_building(w.static_mesh, rng, w.ground, front, pp.yaw + (side > 0 ? M_PI : 0.0), width, depth, h);
        w.objects.push_back({"building", 0, Vec3(front.x(), front.y(), 0.0), pp.yaw, {width, depth, h}});
      }
      if (chance(rng, 0.3 * std::min(1.0, density))) {  // sign pole on the verge
        const Vec2 at = at_offset(road, s + uniform(rng, 0.0, 100.0), side * 15.0);
        add_pole(w.static_mesh, w.ground, at, uniform(rng, 2.5, 4.0), false, 0.0);
      }
    }
    if (chance(rng, 0.5 * std::min(1.0, density)))  // lamp poles on the median
      for (double u = s; u < s + 100.0; u += 50.0) {
        const PathPoint pp = road.at(u);
        add_pole(w.static_mesh, w.ground, pp.p, 10.0, true, pp.yaw + 0.5 * M_PI);
        w.objects.push_back({"street_lamp", 0, Vec3(pp.p.x(), pp.p.y(), 0.0), 0.0, {0.2, 0.2, 10.0}});
      }
  }
}

// Vehicles of one lane, all at `lane_speed` so they never run into each other. In the ego's lane
// they keep clear of the ego (same speed).
void add_lane_traffic(World& w, Rng& rng, const Path& lane_path, bool forward, bool ego_lane,
                      double lane_speed, double ego_s0, double v_ego, double duration, double traffic,
                      const EgoRoute& route) {
  constexpr double kReach = 160.0;
  // Range of start positions (forward lanes: along the ego; oncoming: from the far end) for which
  // the vehicle passes within reach of the ego during the drive.
  double lo, hi;
  if (forward) {
    lo = ego_s0 - kReach - std::max(0.0, lane_speed - v_ego) * duration;
    hi = ego_s0 + kReach + std::max(0.0, v_ego - lane_speed) * duration;
  } else {
    const double ego_rev = lane_path.length() - ego_s0;
    lo = ego_rev - kReach - (lane_speed + v_ego) * duration;
    hi = ego_rev + kReach;
  }
  if (traffic <= 0.0) return;
  const double mean_gap = 65.0 / traffic;
  for (double s = hi - uniform(rng, 0.0, mean_gap); s > lo; s -= uniform(rng, 0.4, 1.6) * mean_gap) {
    Actor a;
    a.kind = chance(rng, lane_speed < 25.0 ? 0.35 : 0.1) ? ActorKind::Truck : ActorKind::Car;
    a.mesh = make_actor_mesh(a.kind, rng, &a.dims);
    a.path = lane_path;
    a.profile = SpeedProfile::constant(lane_speed);
    a.s0 = s;
    s -= a.dims.length;
    if (ego_lane && std::abs(a.s0 - ego_s0) < 0.5 * a.dims.length + 10.0) continue;
    if (!fit_time_window(a, route, 3.0, kReach)) continue;
    a.instance = w.new_instance();
    w.actors.push_back(std::move(a));
  }
}
}  // namespace

World make_highway_world(const ScenarioParams& params) {
  Rng static_rng(stream_seed(params.seed, 1, 0)), traffic_rng(stream_seed(params.seed, 2, 0));
  World w = empty_world(params, 4.0, 900.0, static_rng);
  const double v = params.speed(), duration = params.frames * w.frame_period;
  const double margin = params.max_range + 130.0;
  const double length = v * duration + 2.0 * margin;
  // Centre line: legs of ~400 m with gentle heading changes, rounded with large radii.
  std::vector<Vec2> wp{{0.0, 0.0}};
  double heading = 0.0;
  for (double s = 0.0; s < length + 400.0; s += 400.0) {
    heading += uniform(static_rng, -0.2, 0.2);
    wp.push_back(wp.back() + 400.0 * Vec2(std::cos(heading), std::sin(heading)));
  }
  const Path road = Path::from_waypoints(wp, 900.0, false);
  build_structure(w, road, static_rng, params.density);

  const int ego_lane = 1;  // middle lane
  w.ego.path = road.offset(lane_offset(ego_lane));
  w.ego.s0 = margin;
  w.ego.profile = SpeedProfile::constant(v);
  plan_car(w, params, v, duration, {-kLaneWidth, 0.0, kLaneWidth});  // swerves to the next lanes
  const EgoRoute route = sample_route(w.ego, duration, {}, params.max_range);
  const Path reverse = road.reversed();
  for (int lane = 0; lane < 3; ++lane) {
    const double base = 33.0 - 5.0 * lane;  // fast lane 30-35, middle 25-30, slow 20-25 m/s
    for (bool forward : {true, false}) {
      const Path path = (forward ? road : reverse).offset(lane_offset(lane));
      const bool with_ego = forward && lane == ego_lane;
      const double speed = with_ego ? v : uniform(traffic_rng, base - 3.0, base + 2.0);
      add_lane_traffic(w, traffic_rng, path, forward, with_ego, speed, margin, v, duration, params.traffic,
                       route);
    }
  }
  return w;
}

}  // namespace dloam::sim::detail
