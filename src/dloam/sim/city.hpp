// City of rectangular blocks on a street grid, shared by the `urban` and `loop` scenarios:
// road, blocks raised as sidewalk slabs with curbs, buildings with facade detail, walls, fences,
// trees, street lamps and parked cars (static), then pedestrians, cars and cyclists (moving,
// many of them stop-and-go) near the ego's route.
#pragma once

#include <vector>

#include "dloam/sim/world.hpp"

namespace dloam::sim {

struct CityLayout {
  int nx = 3, ny = 2;     ///< blocks along x and y; street centre lines i = 0..nx, j = 0..ny
  double block = 80.0;    ///< block side, curb to curb (m)
  double street = 16.0;   ///< street width, curb to curb (m)
  double sidewalk = 3.5;  ///< sidewalk ring of every block (m)
  double building_height_max = 28.0;

  [[nodiscard]] double pitch() const { return block + street; }
  [[nodiscard]] double street_x(int i) const { return i * pitch(); }
  [[nodiscard]] double street_y(int j) const { return j * pitch(); }
  /// Block between street lines i, i+1 and j, j+1.
  [[nodiscard]] RaisedArea block_area(int i, int j) const;
};

/// Lateral offsets from a street's centre line (right-hand traffic).
inline constexpr double kLaneOffset = 2.0;
inline constexpr double kBikeOffset = 4.3;
inline constexpr double kParkingOffset = 6.0;

/// A driving direction on a street: horizontal (along x) street j or vertical street i, heading
/// towards increasing (+1) or decreasing (-1) coordinate.
struct StreetLane {
  bool horizontal = true;
  int index = 0;
  int direction = 1;
  bool operator==(const StreetLane& o) const {
    return horizontal == o.horizontal && index == o.index && direction == o.direction;
  }
};

/// Where the ego goes: positions at 10 Hz over the drive, the lanes it drives in (no cars are
/// put there, so nothing drives into the ego), and the distance beyond which an actor may appear
/// or vanish unseen.
struct EgoRoute {
  std::vector<double> times;
  std::vector<Vec2> positions;
  std::vector<StreetLane> ego_lanes;
  double unseen_distance = 130.0;
};
EgoRoute sample_route(const Ego& ego, double duration, std::vector<StreetLane> ego_lanes, double max_range);

/// Static city into world.static_mesh / world.ground / world.objects.
void build_city(World& world, const CityLayout& city, Rng& rng, double density);
/// Moving and standing road users near the route; `traffic` scales their number.
void add_city_traffic(World& world, const CityLayout& city, Rng& rng, double traffic, const EgoRoute& route);

/// Heavy traffic (`traffic` > 1): queues of 1-3 vehicles ahead of and behind the ego in its own
/// lane, at nearly its speed (the co-moving objects that pull a scan matcher along). Deterministic
/// in `rng`; nothing is added at `traffic` <= 1, so default worlds do not change.
void add_ego_flow(World& world, Rng& rng, double traffic, const EgoRoute& route);

/// Sets the actor's existence window [t_begin, t_end] so that it never comes closer than
/// `clearance` to the ego (it would run into it) and appears/vanishes only beyond
/// route.unseen_distance; among the possible windows, the one with the most time within
/// `interest` of the ego. False when no window brings it within `interest`.
bool fit_time_window(Actor& actor, const EgoRoute& route, double clearance, double interest);

}  // namespace dloam::sim
