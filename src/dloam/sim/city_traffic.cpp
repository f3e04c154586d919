// Road users of the city. Pedestrians walk around blocks on the sidewalks, cross streets, stand,
// or stop and go; cars drive in platoons that share one (possibly stop-and-go) speed profile, so
// cars of a lane never overlap; cyclists ride between the lanes and the parked cars. Actors that
// would touch the ego, or never come near it, are dropped. In heavy traffic the ego drives in a
// queue: cars ahead of it and behind it in its own lane move at nearly its speed.
#include <algorithm>
#include <cmath>

#include "dloam/sim/city.hpp"

namespace dloam::sim {

EgoRoute sample_route(const Ego& ego, double duration, std::vector<StreetLane> ego_lanes, double max_range) {
  EgoRoute r;
  for (int k = -10; k <= static_cast<int>(std::ceil(duration * 10.0)) + 10; ++k) {
    r.times.push_back(0.1 * k);
    r.positions.push_back(ego.position(0.1 * k));
  }
  r.ego_lanes = std::move(ego_lanes);
  r.unseen_distance = max_range + 10.0;
  return r;
}

bool fit_time_window(Actor& a, const EgoRoute& route, double clearance, double interest) {
  clearance *= route.clearance_scale;
  const std::size_t n = route.times.size();
  std::vector<double> d(n);
  for (std::size_t k = 0; k < n; ++k)
    d[k] = (a.path.at(a.s0 + a.profile.distance(route.times[k])).p - route.positions[k]).norm();
  // Candidate windows lie between samples where the actor would touch the ego; they must start
  // and end unseen, except at the ends of the drive.
  int best_near = 0;
  std::size_t k = 0;
  while (k < n) {
    std::size_t end = k;
    while (end < n && d[end] >= clearance) ++end;  // [k, end) has no contact
    std::size_t lo = k, hi = end;                  // shrink to unseen boundaries
    if (k > 0)
      while (lo < end && d[lo] <= route.unseen_distance) ++lo;
    if (end < n)
      while (hi > lo && d[hi - 1] <= route.unseen_distance) --hi;
    int near = 0;
    for (std::size_t i = lo; i < hi; ++i) near += d[i] <= interest;
    if (hi > lo && near > best_near) {
      best_near = near;
      a.t_begin = k == 0 ? -1e9 : route.times[lo];
      a.t_end = end == n ? 1e9 : route.times[hi - 1];
    }
    k = end + 1;
  }
  return best_near > 0;
}

namespace {
constexpr double kInterest = 150.0;

std::vector<Vec2> ring(const RaisedArea& r, double inset) {
  return {{r.x0 + inset, r.y0 + inset},
          {r.x1 - inset, r.y0 + inset},
          {r.x1 - inset, r.y1 - inset},
          {r.x0 + inset, r.y1 - inset}};
}

Actor make_actor(Rng& rng, ActorKind kind, Path path, SpeedProfile profile, double s0, bool stop_go) {
  Actor a;
  a.kind = kind;
  a.mesh = make_actor_mesh(kind, rng, &a.dims);
  a.path = std::move(path);
  a.profile = std::move(profile);
  a.s0 = s0;
  a.stop_and_go = stop_go;
  return a;
}

void keep_if_ok(World& w, Actor a, const EgoRoute& route, double clearance) {
  if (!fit_time_window(a, route, clearance, kInterest)) return;
  a.instance = w.new_instance();
  w.actors.push_back(std::move(a));
}

// Straight path along a street lane over the whole city (and beyond, by extrapolation).
Path lane_path(const CityLayout& city, const StreetLane& lane, double offset) {
  const double ext = 60.0;
  const double c = lane.horizontal ? city.street_y(lane.index) : city.street_x(lane.index);
  const double lo = (lane.horizontal ? city.street_x(0) : city.street_y(0)) - ext;
  const double hi = (lane.horizontal ? city.street_x(city.nx) : city.street_y(city.ny)) + ext;
  // Right-hand traffic: heading +x drives at y - offset, heading +y at x + offset.
  const double lateral = lane.horizontal ? c - lane.direction * offset : c + lane.direction * offset;
  Vec2 a = lane.horizontal ? Vec2(lo, lateral) : Vec2(lateral, lo);
  Vec2 b = lane.horizontal ? Vec2(hi, lateral) : Vec2(lateral, hi);
  if (lane.direction < 0) std::swap(a, b);
  return Path::from_waypoints({a, b}, 0.0, false);
}

// Walking speed profile: steady (50 %), stop-and-go (35 %) or, when allowed, standing still (15 %).
SpeedProfile pedestrian_profile(Rng& rng, double duration, bool may_stand, bool* stop_go) {
  const StopAndGo pattern{3.0, 12.0, 2.0, 8.0, 1.0};
  const double v = uniform(rng, 0.9, 1.7), p = uniform(rng, 0.0, 1.0);
  *stop_go = p < 0.35;
  if (*stop_go) return stop_and_go_profile(rng, v, -2.0, duration + 2.0, pattern, chance(rng, 0.5));
  if (p > 0.85 && may_stand) return SpeedProfile::constant(0.0);
  return SpeedProfile::constant(v);
}

// People walking around blocks, some of them crossing a street to the next block first.
void add_block_walkers(World& w, const CityLayout& city, Rng& rng, double traffic, const EgoRoute& route,
                       double duration) {
  for (int i = 0; i < city.nx; ++i)
    for (int j = 0; j < city.ny; ++j) {
      const RaisedArea blk = city.block_area(i, j);
      const int n = static_cast<int>(std::lround(traffic * 4.0 * city.block / 60.0 * uniform(rng, 0.6, 1.4)));
      for (int k = 0; k < n; ++k) {
        std::vector<Vec2> wp = ring(blk, uniform(rng, 1.6, 3.0));
        if (chance(rng, 0.5)) std::reverse(wp.begin(), wp.end());
        const bool crossing = j > 0 && chance(rng, 0.25);
        if (crossing) {
          // Walk along this block, cross the street below it, then walk around the block across.
          const double x = uniform(rng, blk.x0 + 8.0, blk.x1 - 8.0);
          const RaisedArea o = city.block_area(i, j - 1);
          const double y_near = blk.y0 + 2.0, y_far = o.y1 - 2.0;
          wp = {{x - uniform(rng, 10.0, 30.0), y_near},
                {x, y_near},
                {x, y_far},
                {o.x1 - 2.0, y_far},
                {o.x1 - 2.0, o.y0 + 2.0},
                {o.x0 + 2.0, o.y0 + 2.0},
                {o.x0 + 2.0, y_far},
                {x - 1.0, y_far}};
        }
        bool stop_go = false;
        SpeedProfile profile = pedestrian_profile(rng, duration, !crossing, &stop_go);
        Path path = Path::from_waypoints(wp, 1.0, !crossing);
        const double s0 = crossing ? 0.0 : uniform(rng, 0.0, path.length());
        keep_if_ok(w,
                   make_actor(rng, ActorKind::Pedestrian, std::move(path), std::move(profile), s0, stop_go),
                   route, 1.8);
      }
    }
}

// People on the sidewalks of the streets the ego drives along, crossing side streets on the way.
void add_street_walkers(World& w, const CityLayout& city, Rng& rng, double traffic, const EgoRoute& route,
                        double duration) {
  for (const StreetLane& ego_lane : route.ego_lanes)
    for (int dir : {1, -1}) {
      const StreetLane side{ego_lane.horizontal, ego_lane.index, dir};
      const double length = ego_lane.horizontal ? city.street_x(city.nx) - city.street_x(0)
                                                : city.street_y(city.ny) - city.street_y(0);
      const int n = static_cast<int>(std::lround(traffic * length / 20.0 * uniform(rng, 0.8, 1.2)));
      for (int k = 0; k < n; ++k) {
        Path path = lane_path(city, side, 0.5 * city.street + uniform(rng, 1.6, 3.0));
        if (chance(rng, 0.5)) path = path.reversed();
        bool stop_go = false;
        SpeedProfile profile = pedestrian_profile(rng, duration, true, &stop_go);
        const double s0 = uniform(rng, 0.0, path.length());
        keep_if_ok(w,
                   make_actor(rng, ActorKind::Pedestrian, std::move(path), std::move(profile), s0, stop_go),
                   route, 1.8);
      }
    }
}

// A closed circuit around a random rectangle of blocks, driven on the right at `offset`; often one
// side is a street the ego drives along, so that traffic meets the ego.
Path random_circuit(const CityLayout& city, Rng& rng, const EgoRoute& route, double offset) {
  int i0 = uniform_int(rng, 0, city.nx - 1), j0 = uniform_int(rng, 0, city.ny - 1);
  int i1 = uniform_int(rng, i0 + 1, std::min(city.nx, i0 + 3)),
      j1 = uniform_int(rng, j0 + 1, std::min(city.ny, j0 + 3));
  if (!route.ego_lanes.empty() && chance(rng, 0.6)) {
    const StreetLane& e = route.ego_lanes[static_cast<std::size_t>(
        uniform_int(rng, 0, static_cast<int>(route.ego_lanes.size()) - 1))];
    int& lo = e.horizontal ? j0 : i0;
    int& hi = e.horizontal ? j1 : i1;
    const int n = e.horizontal ? city.ny : city.nx;
    if ((chance(rng, 0.5) && e.index < n) || e.index == 0) {
      lo = e.index;
      hi = std::min(n, e.index + uniform_int(rng, 1, 2));
    } else {
      hi = e.index;
      lo = std::max(0, e.index - uniform_int(rng, 1, 2));
    }
  }
  std::vector<Vec2> wp{{city.street_x(i0), city.street_y(j0)},
                       {city.street_x(i1), city.street_y(j0)},
                       {city.street_x(i1), city.street_y(j1)},
                       {city.street_x(i0), city.street_y(j1)}};
  if (chance(rng, 0.5)) std::reverse(wp.begin(), wp.end());
  return Path::from_waypoints(wp, 9.0, true).offset(-offset);
}

// Cars and vans in platoons sharing one speed profile (no overlaps), and cyclists, on circuits.
void add_vehicles(World& w, const CityLayout& city, Rng& rng, double traffic, const EgoRoute& route,
                  double duration) {
  const StopAndGo car_pattern{4.0, 15.0, 3.0, 10.0, 2.0};
  const StopAndGo bike_pattern{5.0, 15.0, 2.0, 6.0, 1.0};
  const int platoons = static_cast<int>(std::lround(traffic * 1.5 * (city.nx + city.ny)));
  for (int p = 0; p < platoons; ++p) {
    const Path path = random_circuit(city, rng, route, kLaneOffset);
    const double v = uniform(rng, 6.0, 12.0);
    const bool stop_go = chance(rng, 0.5);
    const SpeedProfile profile =
        stop_go ? stop_and_go_profile(rng, v, -2.0, duration + 2.0, car_pattern, chance(rng, 0.5))
                : SpeedProfile::constant(v);
    const int n = uniform_int(rng, 1, 3);
    double s = uniform(rng, 0.0, path.length());
    for (int k = 0; k < n; ++k) {
      const ActorKind kind = chance(rng, 0.15) ? ActorKind::Truck : ActorKind::Car;
      Actor a = make_actor(rng, kind, path, profile, s, stop_go);
      s -= a.dims.length + uniform(rng, 3.0, 12.0);  // next car of the platoon behind this one
      keep_if_ok(w, std::move(a), route, 3.5);
    }
  }
  const int cyclists = static_cast<int>(std::lround(traffic * 0.6 * (city.nx + city.ny)));
  for (int k = 0; k < cyclists; ++k) {
    const double v = uniform(rng, 3.0, 6.5);
    const bool stop_go = chance(rng, 0.4);
    SpeedProfile profile =
        stop_go ? stop_and_go_profile(rng, v, -2.0, duration + 2.0, bike_pattern, chance(rng, 0.5))
                : SpeedProfile::constant(v);
    Path path = random_circuit(city, rng, route, kBikeOffset);
    const double s0 = uniform(rng, 0.0, path.length());
    keep_if_ok(w, make_actor(rng, ActorKind::Cyclist, std::move(path), std::move(profile), s0, stop_go),
               route, 1.8);
  }
}
}  // namespace

bool overlaps(const Actor& a, const Actor& other, const EgoRoute& route) {
  const double reach = 0.5 * std::max(other.dims.length, other.dims.width);
  for (double t : route.times) {
    if (!a.present(t) || !other.present(t)) continue;
    const PathPoint pa = a.path.at(a.s0 + a.profile.distance(t));
    const Vec2 d = other.path.at(other.s0 + other.profile.distance(t)).p - pa.p;
    const double along = std::cos(pa.yaw) * d.x() + std::sin(pa.yaw) * d.y();
    const double across = -std::sin(pa.yaw) * d.x() + std::cos(pa.yaw) * d.y();
    if (std::abs(along) < 0.5 * a.dims.length + reach && std::abs(across) < 0.5 * a.dims.width + reach)
      return true;
  }
  return false;
}

void add_ego_flow(World& w, Rng& rng, double traffic, const EgoRoute& route) {
  // Chance of a queue ahead and of one behind: none up to the default traffic, certain from 3x.
  const double p = std::clamp(0.5 * (traffic - 1.0), 0.0, 1.0);
  const double v = w.ego.profile.speed(0.0);
  for (int side : {1, -1}) {
    if (!chance(rng, p)) continue;
    // Ahead: slowly pulling away; behind: slowly falling back, so the queue never closes on the ego.
    const SpeedProfile profile = SpeedProfile::constant(std::max(0.0, v + side * uniform(rng, 0.0, 0.4)));
    double s = w.ego.s0 + side * uniform(rng, 7.0, 15.0);
    const int n = uniform_int(rng, 1, 3);
    for (int k = 0; k < n; ++k) {
      const ActorKind kind = chance(rng, 0.15) ? ActorKind::Truck : ActorKind::Car;
      Actor a = make_actor(rng, kind, w.ego.path, profile, s, false);
      a.s0 += side * 0.5 * a.dims.length;  // the mesh origin is the vehicle's centre
      s += side * (a.dims.length + uniform(rng, 3.0, 8.0));
      if (!fit_time_window(a, route, 3.5, kInterest)) continue;
      // The queue owns its stretch of lane: road users that would drive or walk through it go.
      w.actors.erase(std::remove_if(w.actors.begin(), w.actors.end(),
                                    [&](const Actor& o) { return overlaps(a, o, route); }),
                     w.actors.end());
      a.instance = w.new_instance();
      w.actors.push_back(std::move(a));
    }
  }
}

void add_city_traffic(World& w, const CityLayout& city, Rng& rng, double traffic, const EgoRoute& route) {
  const double duration = route.times.empty() ? 0.0 : route.times.back();
  add_street_walkers(w, city, rng, traffic, route, duration);
  add_block_walkers(w, city, rng, traffic, route, duration);
  add_vehicles(w, city, rng, traffic, route, duration);
}

}  // namespace dloam::sim
