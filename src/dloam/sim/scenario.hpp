// Scenario generators (DLOAM paper, Sec. V: Scenario 1 urban with many pedestrians and
// stop-and-go objects; Scenario 2 highway with many fast vehicles):
//   urban   - a straight drive down a city street: many pedestrians, some cars and cyclists;
//   highway - 3+3 lanes, vehicles at 20-35 m/s both ways, guard rails, fences, sparse trees/poles;
//   loop    - a drive around a closed circuit of city blocks that returns to its start;
//   spin    - the sensor standing in the urban street, turning on the spot at a constant rate
//             (a known answer: scan-to-scan motion is a pure rotation of rate / scan rate);
//   tunnel  - a city street, then a long straight tunnel (walls and ceiling, few features along
//             the driving direction), then a city street again;
//   open-field - a city street, then a road across flat open ground with very few vertical
//             structures, then a city street again.
// The ego platform (urban: car, handheld or legged) and its events (car: swerves, hard braking)
// are options, as are scripted objects for map cleaning (urban). The same params (seed
// included) always give the same world, bit for bit; the default options give the worlds of
// earlier versions.
#pragma once

#include <cstdint>
#include <string>

#include "dloam/sim/platform.hpp"
#include "dloam/sim/world.hpp"

namespace dloam::sim {

enum class ScenarioKind { Urban, Highway, Loop, Spin, Tunnel, OpenField };

struct ScenarioParams {
  ScenarioKind kind = ScenarioKind::Urban;
  int frames = 200;  ///< sweeps the world must cover (10 Hz), 1..20000
  std::uint64_t seed = 1;
  double density = 1.0;               ///< static scene density (trees, poles, parked cars, walls), 0..5
  double traffic = 1.0;               ///< number of road users relative to the default, 0..10
  double ego_speed = 0.0;             ///< m/s; 0: the scenario's default (urban 7, loop 9, highway 25)
  double hills = -1.0;                ///< terrain undulation amplitude (m); negative: the scenario's default
  double max_range = 120.0;           ///< sensor range, to size the world around the drive
  Platform platform = Platform::Car;  ///< handheld / legged: urban only
  bool swerve = false;                ///< car: lane-change swerves (urban, highway, tunnel, open-field)
  bool brake = false;                 ///< car: hard braking to standstill and away again
  double spin_rate_deg = 90.0;        ///< spin: yaw rate (deg/s, > 0 counter-clockwise)
  /// urban: a pedestrian standing for the first half of the drive then walking away, one walking
  /// in and standing for the second half, and a parked car that drives off after `leave_after`
  /// scans (-1: a third of the frames).
  bool cleaning_actors = false;
  int leave_after = -1;

  /// Throws std::invalid_argument naming the bad parameter.
  void validate() const;
  [[nodiscard]] double speed() const;  ///< ego_speed or the default of the scenario and platform
  /// Scans after which the scripted parked car drives off.
  [[nodiscard]] int leave_after_frames() const { return leave_after >= 0 ? leave_after : frames / 3; }
};

/// "urban" | "highway" | "loop" | "spin" | "tunnel" | "open-field" (case-insensitive); throws
/// std::invalid_argument otherwise.
ScenarioKind parse_scenario_kind(const std::string& name);
std::string to_string(ScenarioKind kind);
double default_ego_speed(ScenarioKind kind);

/// Builds the world of a scenario.
World make_world(const ScenarioParams& params);

namespace detail {
/// A world with no objects yet: the scenario name and the ground (undulation `default_hills` m
/// unless params.hills is given, `wavelength` m, random phases drawn from `static_rng`).
World empty_world(const ScenarioParams& params, double default_hills, double wavelength, Rng& static_rng);
World make_city_world(const ScenarioParams& params, bool loop);
World make_highway_world(const ScenarioParams& params);
/// tunnel (`tunnel` true) or open-field.
World make_transit_world(const ScenarioParams& params, bool tunnel);
/// Cruise speed v, swerves and braking of the car for `params`; `lanes` as in plan_drive_events.
void plan_car(World& world, const ScenarioParams& params, double v, double duration,
              const std::vector<double>& lanes);
}  // namespace detail

}  // namespace dloam::sim
