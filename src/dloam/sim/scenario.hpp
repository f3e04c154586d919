// Scenario generators (DLOAM paper, Sec. V: Scenario 1 urban with many pedestrians and
// stop-and-go objects; Scenario 2 highway with many fast vehicles):
//   urban   - a straight drive down a city street: many pedestrians, some cars and cyclists;
//   highway - 3+3 lanes, vehicles at 20-35 m/s both ways, guard rails, fences, sparse trees/poles;
//   loop    - a drive around a closed circuit of city blocks that returns to its start.
// The same params (seed included) always give the same world, bit for bit.
#pragma once

#include <cstdint>
#include <string>

#include "dloam/sim/world.hpp"

namespace dloam::sim {

enum class ScenarioKind { Urban, Highway, Loop };

struct ScenarioParams {
  ScenarioKind kind = ScenarioKind::Urban;
  int frames = 200;  ///< sweeps the world must cover (10 Hz), 1..20000
  std::uint64_t seed = 1;
  double density = 1.0;      ///< static scene density (trees, poles, parked cars, walls), 0..5
  double traffic = 1.0;      ///< number of road users relative to the default, 0..10
  double ego_speed = 0.0;    ///< m/s; 0: the scenario's default (urban 7, loop 9, highway 25)
  double hills = -1.0;       ///< terrain undulation amplitude (m); negative: the scenario's default
  double max_range = 120.0;  ///< sensor range, to size the world around the drive

  /// Throws std::invalid_argument naming the bad parameter.
  void validate() const;
  [[nodiscard]] double speed() const;  ///< ego_speed or the default
};

/// "urban" | "highway" | "loop" (case-insensitive); throws std::invalid_argument otherwise.
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
}  // namespace detail

}  // namespace dloam::sim
