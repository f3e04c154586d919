// Scenario parameters, dispatch, and the two city scenarios (urban street, loop around blocks).
#include "dloam/sim/scenario.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dloam/sim/city.hpp"

namespace dloam::sim {

ScenarioKind parse_scenario_kind(const std::string& name) {
  std::string n = name;
  for (auto& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (n == "urban") return ScenarioKind::Urban;
  if (n == "highway") return ScenarioKind::Highway;
  if (n == "loop") return ScenarioKind::Loop;
  if (n == "spin") return ScenarioKind::Spin;
  if (n == "tunnel") return ScenarioKind::Tunnel;
  if (n == "open-field") return ScenarioKind::OpenField;
  throw std::invalid_argument("unknown scenario '" + name +
                              "' (known: urban, highway, loop, spin, tunnel, open-field)");
}

std::string to_string(ScenarioKind kind) {
  switch (kind) {
    case ScenarioKind::Urban:
      return "urban";
    case ScenarioKind::Highway:
      return "highway";
    case ScenarioKind::Loop:
      return "loop";
    case ScenarioKind::Spin:
      return "spin";
    case ScenarioKind::Tunnel:
      return "tunnel";
    case ScenarioKind::OpenField:
      return "open-field";
  }
  return "unknown";
}

double default_ego_speed(ScenarioKind kind) {
  switch (kind) {
    case ScenarioKind::Urban:
      return 7.0;
    case ScenarioKind::Highway:
      return 25.0;
    case ScenarioKind::Loop:
      return 9.0;
    case ScenarioKind::Spin:
      return 0.0;
    case ScenarioKind::Tunnel:
    case ScenarioKind::OpenField:
      return 10.0;
  }
  return 7.0;
}

double ScenarioParams::speed() const {
  if (kind == ScenarioKind::Spin) return 0.0;
  if (ego_speed > 0.0) return ego_speed;
  return platform == Platform::Car ? default_ego_speed(kind) : default_platform_speed(platform);
}

void ScenarioParams::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("scenario: " + what); };
  if (frames < 1 || frames > 20000) fail("frames must be in [1, 20000], got " + std::to_string(frames));
  if (!(density >= 0.0 && density <= 5.0)) fail("density must be in [0, 5]");
  if (!(traffic >= 0.0 && traffic <= 10.0)) fail("traffic must be in [0, 10]");
  if (!(ego_speed >= 0.0 && ego_speed <= 50.0)) fail("ego speed must be in [0, 50] m/s (0: default)");
  if (!(hills <= 20.0)) fail("hills must be at most 20 m");
  if (!(max_range > 0.0 && max_range <= 500.0)) fail("max range must be in (0, 500] m");
  const bool walker = platform != Platform::Car;
  if (walker && kind != ScenarioKind::Urban)
    fail("the " + to_string(platform) + " platform walks the urban street only (--scenario urban)");
  if (walker && ego_speed > 0.0 && !(ego_speed >= 0.5 && ego_speed <= 2.5))
    fail("a walking speed must be in [0.5, 2.5] m/s");
  if ((swerve || brake) && walker) fail("swerves and braking are car manoeuvres (--platform car)");
  if (swerve && (kind == ScenarioKind::Loop || kind == ScenarioKind::Spin))
    fail("swerves need a straight road: urban, highway, tunnel or open-field");
  if (brake && kind == ScenarioKind::Spin) fail("the spin scenario does not drive: no braking");
  if (kind == ScenarioKind::Spin && !(std::abs(spin_rate_deg) > 0.0 && std::abs(spin_rate_deg) <= 720.0))
    fail("spin rate must be non-zero and at most 720 deg/s in magnitude");
  if (cleaning_actors && kind != ScenarioKind::Urban)
    fail("the map-cleaning objects are in the urban street");
  if (cleaning_actors && swerve)
    fail("the map-cleaning objects and swerves into their lane exclude each other");
  if (leave_after < -1 || leave_after > frames) fail("leave-after must be in [0, frames] scans");
  // The urban street and the highway are built along the whole drive; the loop is driven in laps.
  const double drive_km = speed() * frames * 0.1 / 1000.0;
  const double max_km = kind == ScenarioKind::Highway ? 50.0 : kind == ScenarioKind::Loop ? 1e9 : 5.0;
  if (drive_km > max_km) {
    char msg[160];
    std::snprintf(msg, sizeof(msg),
                  "%s drive of %.1f km is longer than %.0f km (fewer frames, lower speed, or loop)",
                  to_string(kind).c_str(), drive_km, max_km);
    fail(msg);
  }
}

World make_world(const ScenarioParams& params) {
  params.validate();
  switch (params.kind) {
    case ScenarioKind::Urban:
    case ScenarioKind::Spin:
      return detail::make_city_world(params, false);
    case ScenarioKind::Loop:
      return detail::make_city_world(params, true);
    case ScenarioKind::Highway:
      return detail::make_highway_world(params);
    case ScenarioKind::Tunnel:
      return detail::make_transit_world(params, true);
    case ScenarioKind::OpenField:
      return detail::make_transit_world(params, false);
  }
  throw std::invalid_argument("unknown scenario kind");
}

namespace detail {

World empty_world(const ScenarioParams& params, double default_hills, double wavelength, Rng& static_rng) {
  World w;
  w.scenario = to_string(params.kind);
  w.ground.amplitude = params.hills >= 0.0 ? params.hills : default_hills;
  w.ground.wavelength = wavelength;
  w.ground.phase_x = uniform(static_rng, 0.0, 2.0 * M_PI);
  w.ground.phase_y = uniform(static_rng, 0.0, 2.0 * M_PI);
  return w;
}

World make_city_world(const ScenarioParams& params, bool loop) {
  Rng static_rng(stream_seed(params.seed, 1, 0)), traffic_rng(stream_seed(params.seed, 2, 0));
  World w = empty_world(params, 2.0, 420.0, static_rng);
  const double v = params.speed();
  const double duration = params.frames * w.frame_period;
  const bool walker = params.platform != Platform::Car;
  const double drive = (walker ? v + 0.5 : v) * duration;  // walkers: legs up to 0.5 m/s faster
  CityLayout city;
  std::vector<StreetLane> ego_lanes;
  if (!loop) {
    // Main street j = 2 between two rows of blocks on each side; the ego drives +x in its right lane.
    city.ny = 4;
    const double start = city.pitch() * 1.5;
    city.nx = static_cast<int>(std::ceil((start + drive + params.max_range + 30.0) / city.pitch()));
    const double y = city.street_y(2) - kLaneOffset;
    w.ego.path = Path::from_waypoints({{-200.0, y}, {city.street_x(city.nx) + 200.0 + drive, y}}, 0.0, false);
    w.ego.s0 = start + 200.0;
    ego_lanes.push_back({true, 2, 1});
  } else {
    // Counter-clockwise around a x b blocks (a ring of blocks outside), right lane (outer side).
    // Lap about as long as the drive (at least ~400 m, at most ~2.5 km: longer drives do laps).
    const int blocks = std::clamp(static_cast<int>(std::lround(drive / (2.0 * city.pitch()))), 2, 13);
    const int a = (blocks + 1) / 2, b = blocks - a;
    city.nx = a + 2;
    city.ny = b + 2;
    const double x0 = city.street_x(1), x1 = city.street_x(a + 1), y0 = city.street_y(1),
                 y1 = city.street_y(b + 1);
    // Corners: arcs of 10 m entered and left through clothoids, so the yaw rate ramps with at most
    // kMaxYawAcceleration (at most a pure spiral when the speed is high).
    constexpr double kCornerRadius = 10.0, kMaxYawAcceleration = 0.6;  // m, rad/s^2
    const double transition = v * v / (kCornerRadius * kMaxYawAcceleration);
    const Path centre =
        Path::from_waypoints({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, kCornerRadius, true, transition);
    w.ego.path = centre.offset(-kLaneOffset);
    w.ego.s0 = 0.5 * (x1 - x0) - 10.0;
    ego_lanes = {{true, 1, 1}, {false, a + 1, 1}, {true, b + 1, -1}, {false, 1, -1}};
  }
  w.ego.profile = SpeedProfile::constant(v);
  double clearance_scale = 1.0;
  if (params.kind == ScenarioKind::Spin) {
    plan_spin(w.ego, params.spin_rate_deg * M_PI / 180.0);
  } else if (walker) {
    // On the sidewalks of the main street, 0.6 m from the curb (people walk farther in), crossing
    // the street now and then; road users may pass a walker at arm's length.
    const double y_near = city.street_y(2) - (0.5 * city.street + 0.6);
    const double y_far = city.street_y(2) + (0.5 * city.street + 0.6);
    const WalkStyle style = params.platform == Platform::Handheld ? handheld_style(v) : legged_style(v);
    Rng walk_rng(stream_seed(params.seed, 4, 0));
    const std::vector<double> crossings =
        plan_walk(w.ego, style, walk_rng, {w.ego.path.at(w.ego.s0).p.x(), y_near}, y_far, duration);
    // Where the walk crosses, no car is parked and no pole or tree stands at the curb: a parked car
    // reaches 3.2 m along the street from its slot's centre, and the walker passes at arm's length.
    constexpr double kCrossingClear = 4.0;  // m on each side of the crossing line
    for (const double x : crossings)
      city.keep_clear.push_back({x - kCrossingClear, std::min(y_near, y_far) - 1.0, x + kCrossingClear,
                                 std::max(y_near, y_far) + 1.0, 0.0});
    clearance_scale = 0.5;
  } else {
    plan_car(w, params, v, duration,
             loop ? std::vector<double>{0.0} : std::vector<double>{0.0, 2.0 * kLaneOffset});
  }
  std::vector<Actor> scripted;
  if (params.cleaning_actors) {
    Rng scripted_rng(stream_seed(params.seed, 6, 0));
    const double t_leave = params.leave_after_frames() * w.frame_period;
    scripted = cleaning_actors(w.ego, city, 2, duration, t_leave, scripted_rng, &city.keep_clear);
  }
  build_city(w, city, static_rng, params.density);
  EgoRoute route = sample_route(w.ego, duration, ego_lanes, params.max_range);
  route.clearance_scale = clearance_scale;
  add_city_traffic(w, city, traffic_rng, params.traffic, route);
  Rng flow_rng(stream_seed(params.seed, 3, 0));  // own stream: the other road users stay the same
  add_ego_flow(w, flow_rng, params.traffic, route);
  for (Actor& a : scripted) {
    // The scripted objects own their place: road users that would drive or walk through them go.
    w.actors.erase(std::remove_if(w.actors.begin(), w.actors.end(),
                                  [&](const Actor& o) { return overlaps(a, o, route); }),
                   w.actors.end());
    a.instance = w.new_instance();
    w.actors.push_back(std::move(a));
  }
  return w;
}

void plan_car(World& w, const ScenarioParams& params, double v, double duration,
              const std::vector<double>& lanes) {
  if (!params.swerve && !params.brake) return;  // cruising at v, as set by the scenario
  Rng event_rng(stream_seed(params.seed, 5, 0));
  plan_drive_events(w.ego, event_rng, v, duration, params.swerve, params.brake, lanes);
}

}  // namespace detail
}  // namespace dloam::sim
