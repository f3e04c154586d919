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
  double x0 = 0.0;                            ///< x of street line i = 0
  double margin_x0 = 40.0, margin_x1 = 40.0;  ///< road beyond the first / last street line along x
  /// Rectangles (height unused) where no car is parked and no tree or pole stands, e.g. the slot
  /// of a scripted car; the rest of the city is the same with or without them.
  std::vector<RaisedArea> keep_clear;

  [[nodiscard]] double pitch() const { return block + street; }
  [[nodiscard]] double street_x(int i) const { return x0 + i * pitch(); }
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
  double clearance_scale = 1.0;  ///< scales every clearance to the ego (a walker: 0.5)
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

/// Whether `other` ever overlaps the vehicle `a` (footprint box against other's half length) while
/// both exist, sampled at the route's times.
bool overlaps(const Actor& a, const Actor& other, const EgoRoute& route);

/// Scripted objects for map cleaning beside the ego's drive along +x on horizontal street `j`
/// (instances unset, roles "stand_then_walk", "walk_then_stand", "leaving_car"):
///   - a pedestrian standing on the right sidewalk until half the drive, then walking away;
///   - a pedestrian walking in on the left sidewalk and standing from half the drive on;
///   - a car parked at the left curb, 18 m ahead of where the ego is at `t_leave`, that pulls out
///     into the left lane at `t_leave` and drives off against the ego's direction.
/// Adds the car's parking slot and the curb beside the pedestrians and 25 m before them to
/// `keep_clear`, so that parked cars, trees and poles do not hide them from the approaching ego.
std::vector<Actor> cleaning_actors(const Ego& ego, const CityLayout& city, int j, double duration,
                                   double t_leave, Rng& rng, std::vector<RaisedArea>* keep_clear);

/// Sets the actor's existence window [t_begin, t_end] so that it never comes closer than
/// `clearance` (times route.clearance_scale) to the ego (it would run into it) and appears/vanishes only
/// beyond route.unseen_distance; among the possible windows, the one with the most time within `interest` of
/// the ego. False when no window brings it within `interest`.
bool fit_time_window(Actor& actor, const EgoRoute& route, double clearance, double interest);

}  // namespace dloam::sim
