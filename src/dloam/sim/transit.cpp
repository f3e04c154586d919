// Scenarios tunnel and open-field: a city street between two rows of blocks, then a long straight
// stretch of the same road inside a tunnel (smooth walls and ceiling, lamps) or across flat open
// ground (a few poles and distant trees), then a city street again. The drive starts in structure,
// loses it for most of the way and finds it again at the end, so recovery can be tested.
#include <algorithm>
#include <cmath>

#include "dloam/sim/city.hpp"
#include "dloam/sim/props.hpp"
#include "dloam/sim/scenario.hpp"

namespace dloam::sim::detail {

namespace {
constexpr double kTunnelHalfWidth = 5.5;  // wall to road centre (m): two 4 m lanes and margins
constexpr double kTunnelHeight = 6.0;     // ceiling above the road (m)
constexpr double kPortalHeight = 25.0;    // hillside face around each tunnel mouth (m)
constexpr double kRoadHalfWidth = 6.0;    // open-field road (m)
constexpr double kCell = 4.0;

struct Span {
  double x0, x1, yc, y_lo, y_hi;
};

// A wall face from the terrain up to `height` above it along y = y, following the terrain.
void add_tunnel_wall(Mesh& mesh, const Ground& g, double x0, double x1, double y, double height, Material m) {
  const int n = std::max(1, static_cast<int>(std::ceil((x1 - x0) / kCell)));
  for (int i = 0; i < n; ++i) {
    const double a = x0 + (x1 - x0) * i / n, b = x0 + (x1 - x0) * (i + 1) / n;
    const double za = g.terrain(a, y), zb = g.terrain(b, y);
    add_quad(mesh, Vec3(a, y, za - 0.3), Vec3(b, y, zb - 0.3), Vec3(b, y, zb + height),
             Vec3(a, y, za + height), m);
  }
}

// The face of the hill around a tunnel mouth at x (the opening: |y - yc| < half width, below the ceiling).
void add_portal(Mesh& mesh, const Ground& g, const Span& s, double x, double thickness) {
  const Material m{cls::kBuilding, 0.4f};
  const double w = kTunnelHalfWidth;
  auto lowest = [&](double y0, double y1) {
    double z = 1e9;
    for (int k = 0; k <= 20; ++k) z = std::min(z, g.terrain(x, y0 + (y1 - y0) * k / 20.0));
    return z - 1.0;
  };
  const double z_top = g.terrain(x, s.yc) + kPortalHeight;
  add_box_z(mesh, x, 0.5 * (s.y_lo + s.yc - w), 0.0, thickness, s.yc - w - s.y_lo, lowest(s.y_lo, s.yc - w),
            z_top, m);
  add_box_z(mesh, x, 0.5 * (s.yc + w + s.y_hi), 0.0, thickness, s.y_hi - s.yc - w, lowest(s.yc + w, s.y_hi),
            z_top, m);
  add_box_z(mesh, x, s.yc, 0.0, thickness, 2.0 * w, g.terrain(x, s.yc) + kTunnelHeight, z_top, m);
}

void build_tunnel(World& w, const Span& s) {
  const Ground& g = w.ground;
  const double hw = kTunnelHalfWidth;
  add_ground_grid(w.static_mesh, g, s.x0, s.yc - hw, s.x1, s.yc + hw, kCell, 0.0, [](double, double) {
    return Material{cls::kRoad, 0.22f};
  });
  add_ground_grid(w.static_mesh, g, s.x0, s.yc - hw - 0.3, s.x1, s.yc + hw + 0.3, kCell, kTunnelHeight,
                  [](double, double) {
                    return Material{cls::kBuilding, 0.4f};
                  });
  for (double side : {-1.0, 1.0})
    add_tunnel_wall(w.static_mesh, g, s.x0, s.x1, s.yc + side * hw, kTunnelHeight + 0.1,
                    {cls::kBuilding, 0.45f});
  // Lamps under the ceiling every 25 m: the only features along the tunnel.
  for (double x = s.x0 + 12.5; x < s.x1 - 5.0; x += 25.0) {
    const double z = g.terrain(x, s.yc) + kTunnelHeight;
    add_box_z(w.static_mesh, x, s.yc, 0.0, 1.2, 0.3, z - 0.15, z + 0.01, {cls::kPole, 0.7f});
  }
  add_portal(w.static_mesh, g, s, s.x0 - 0.4, 0.8);
  add_portal(w.static_mesh, g, s, s.x1 + 0.4, 0.8);
}

void build_field(World& w, Rng& rng, const Span& s, double density) {
  const Ground& g = w.ground;
  const double r = kRoadHalfWidth;
  add_ground_grid(w.static_mesh, g, s.x0, s.yc - r, s.x1, s.yc + r, kCell, 0.0, [](double, double) {
    return Material{cls::kRoad, 0.22f};
  });
  add_ground_grid(w.static_mesh, g, s.x0, s.y_lo, s.x1, s.yc - r, kCell, 0.0, [](double, double) {
    return Material{cls::kTerrain, 0.3f};
  });
  add_ground_grid(w.static_mesh, g, s.x0, s.yc + r, s.x1, s.y_hi, kCell, 0.0, [](double, double) {
    return Material{cls::kTerrain, 0.3f};
  });
  // Very few vertical structures: a sign pole now and then, a few distant trees.
  for (double x = s.x0 + uniform(rng, 60.0, 150.0); x < s.x1 - 20.0; x += uniform(rng, 150.0, 260.0)) {
    if (!chance(rng, std::min(1.0, 0.8 * density))) continue;
    const Vec2 at(x, s.yc - r - 2.0);
    const double h = uniform(rng, 2.5, 3.5);
    add_pole(w.static_mesh, g, at, h, false, 0.0);
    w.objects.push_back({"pole", 0, Vec3(at.x(), at.y(), 0.0), 0.0, {0.2, 0.2, h}});
  }
  for (double x = s.x0 + uniform(rng, 40.0, 120.0); x < s.x1 - 20.0; x += uniform(rng, 120.0, 220.0)) {
    if (!chance(rng, std::min(1.0, 0.7 * density))) continue;
    const double side = chance(rng, 0.5) ? 1.0 : -1.0;
    const Vec2 at(x, s.yc + side * uniform(rng, 30.0, 90.0));
    const double h = uniform(rng, 6.0, 12.0);
    add_tree(w.static_mesh, rng, g, at, h);
    w.objects.push_back({"tree", 0, Vec3(at.x(), at.y(), 0.0), 0.0, {h * 0.4, h * 0.4, h}});
  }
}

// Cars on the road through the whole world: oncoming in the left lane, and a few ahead in the
// ego's lane pulling slowly away.
void add_through_traffic(World& w, Rng& rng, double traffic, const EgoRoute& route, double yc, double x_lo,
                         double x_hi, double v_ego) {
  if (traffic <= 0.0) return;
  const Path oncoming =
      Path::from_waypoints({{x_hi, yc + kLaneOffset}, {x_lo, yc + kLaneOffset}}, 0.0, false);
  const Path ahead = Path::from_waypoints({{x_lo, yc - kLaneOffset}, {x_hi, yc - kLaneOffset}}, 0.0, false);
  const double mean_gap = 90.0 / traffic;
  for (int lane = 0; lane < 2; ++lane) {
    const Path& path = lane == 0 ? oncoming : ahead;
    const double v = lane == 0 ? uniform(rng, 9.0, 14.0) : v_ego + uniform(rng, 0.3, 1.0);
    for (double s = uniform(rng, 0.0, mean_gap); s < path.length(); s += uniform(rng, 0.5, 1.5) * mean_gap) {
      Actor a;
      a.kind = chance(rng, 0.15) ? ActorKind::Truck : ActorKind::Car;
      a.mesh = make_actor_mesh(a.kind, rng, &a.dims);
      a.path = path;
      a.profile = SpeedProfile::constant(v);
      a.s0 = s;
      s += a.dims.length;
      if (!fit_time_window(a, route, 3.5, 150.0)) continue;
      a.instance = w.new_instance();
      w.actors.push_back(std::move(a));
    }
  }
}
}  // namespace

World make_transit_world(const ScenarioParams& params, bool tunnel) {
  Rng static_rng(stream_seed(params.seed, 1, 0)), traffic_rng(stream_seed(params.seed, 2, 0));
  World w = empty_world(params, tunnel ? 1.0 : 0.5, 420.0, static_rng);
  const double v = params.speed(), duration = params.frames * w.frame_period, drive = v * duration;
  // Structured lead-in and lead-out of 15 % of the drive each (20-60 m), the rest in between.
  const double lead = std::clamp(0.15 * drive, 20.0, 60.0);
  CityLayout a;
  a.nx = 2;
  a.ny = 2;
  a.margin_x1 = 0.0;
  const double yc = a.street_y(1), x_in = a.street_x(a.nx) + 0.5 * a.street;
  const double start = x_in - lead, x_out = x_in + std::max(20.0, drive - 2.0 * lead);
  CityLayout b = a;
  b.x0 = x_out + 0.5 * b.street;
  b.margin_x0 = 0.0;
  b.margin_x1 = 40.0;
  b.nx =
      std::max(2, static_cast<int>(std::ceil((start + drive + params.max_range + 30.0 - b.x0) / b.pitch())));
  const double y = yc - kLaneOffset;
  w.ego.path = Path::from_waypoints({{-200.0, y}, {b.street_x(b.nx) + 200.0 + drive, y}}, 0.0, false);
  w.ego.s0 = start + 200.0;
  w.ego.profile = SpeedProfile::constant(v);
  plan_car(w, params, v, duration, {0.0, 2.0 * kLaneOffset});
  build_city(w, a, static_rng, params.density);
  build_city(w, b, static_rng, params.density);
  const double h = 0.5 * a.street;
  const Span span{x_in, x_out, yc, a.street_y(0) - h - 50.0, a.street_y(a.ny) + h + 50.0};
  if (tunnel) {
    build_tunnel(w, span);
  } else {
    build_field(w, static_rng, span, params.density);
  }
  const EgoRoute route = sample_route(w.ego, duration, {{true, 1, 1}}, params.max_range);
  add_city_traffic(w, a, traffic_rng, params.traffic, route);
  add_city_traffic(w, b, traffic_rng, params.traffic, route);
  add_through_traffic(w, traffic_rng, params.traffic, route, yc, a.street_x(0) - 60.0,
                      b.street_x(b.nx) + 60.0, v);
  return w;
}

}  // namespace dloam::sim::detail
