// Static part of the city: ground, blocks, lots along each block side (buildings, walls, fences),
// street furniture on the sidewalks and parked cars along the curbs.
#include "dloam/sim/city.hpp"

#include <algorithm>
#include <cmath>

#include "dloam/sim/props.hpp"

namespace dloam::sim {

RaisedArea CityLayout::block_area(int i, int j) const {
  const double h = 0.5 * street;
  return {street_x(i) + h, street_y(j) + h, street_x(i + 1) - h, street_y(j + 1) - h, 0.15};
}

namespace {
constexpr double kMargin = 40.0;  // road beyond the outermost streets along y

// One side of a block: from `a` to `b` along the curb, outward normal given by `yaw` (facade frame).
struct Side {
  Vec2 a, b;
  double yaw;
};

std::vector<Side> sides_of(const RaisedArea& r, double inset) {
  return {{{r.x0 + inset, r.y0 + inset}, {r.x1 - inset, r.y0 + inset}, M_PI},
          {{r.x1 - inset, r.y0 + inset}, {r.x1 - inset, r.y1 - inset}, -0.5 * M_PI},
          {{r.x1 - inset, r.y1 - inset}, {r.x0 + inset, r.y1 - inset}, 0.0},
          {{r.x0 + inset, r.y1 - inset}, {r.x0 + inset, r.y0 + inset}, 0.5 * M_PI}};
}

void add_block_ground(World& w, const RaisedArea& r, double sidewalk) {
  auto material = [&](double x, double y) {
    const bool ring =
        x < r.x0 + sidewalk || x > r.x1 - sidewalk || y < r.y0 + sidewalk || y > r.y1 - sidewalk;
    return ring ? Material{cls::kSidewalk, 0.35f} : Material{cls::kTerrain, 0.3f};
  };
  add_ground_grid(w.static_mesh, w.ground, r.x0, r.y0, r.x1, r.y1, sidewalk / 2.0, r.height, material);
  const Vec2 c[4] = {{r.x0, r.y0}, {r.x1, r.y0}, {r.x1, r.y1}, {r.x0, r.y1}};
  for (int k = 0; k < 4; ++k)
    add_curb(w.static_mesh, w.ground, c[k], c[(k + 1) % 4], r.height, 4.0, {cls::kSidewalk, 0.35f});
}

void add_lots(World& w, Rng& rng, const CityLayout& city, const Side& side) {
  const Vec2 dir = (side.b - side.a).normalized();
  const Vec2 out(-std::sin(side.yaw), std::cos(side.yaw));
  const double length = (side.b - side.a).norm();
  for (double x = 0.0; x < length - 4.0;) {
    const double width = std::min(uniform(rng, 10.0, 28.0), length - x);
    const double setback = uniform(rng, 0.0, 1.0);
    const Vec2 front = side.a + (x + 0.5 * width) * dir - setback * out;
    const double p = uniform(rng, 0.0, 1.0);
    if (p < 0.75) {
      const double depth = uniform(rng, 10.0, 24.0), height = uniform(rng, 6.0, city.building_height_max);
      add_building(w.static_mesh, rng, w.ground, front, side.yaw, width - 0.2, depth, height);
      w.objects.push_back({"building", 0, Vec3(front.x(), front.y(), 0.0), side.yaw, {width, depth, height}});
    } else if (p < 0.87) {
      const double h = uniform(rng, 1.4, 2.6);
      add_wall(w.static_mesh, w.ground, side.a + x * dir, side.a + (x + width) * dir, h, 0.3);
      w.objects.push_back({"wall", 0, Vec3(front.x(), front.y(), 0.0), side.yaw, {width, 0.3, h}});
    } else if (p < 0.97) {
      const double h = uniform(rng, 1.2, 2.0);
      add_fence(w.static_mesh, w.ground, side.a + x * dir, side.a + (x + width) * dir, h);
      w.objects.push_back({"fence", 0, Vec3(front.x(), front.y(), 0.0), side.yaw, {width, 0.05, h}});
    }
    x += width;
  }
}

bool kept_clear(const std::vector<RaisedArea>& keep_clear, const Vec2& at) {
  return std::any_of(keep_clear.begin(), keep_clear.end(),
                     [&](const RaisedArea& r) { return r.contains(at.x(), at.y()); });
}

void add_street_furniture(World& w, Rng& rng, const Side& curb, double density,
                          const std::vector<RaisedArea>& keep_clear) {
  const Vec2 dir = (curb.b - curb.a).normalized();
  const Vec2 out(-std::sin(curb.yaw), std::cos(curb.yaw));
  const double length = (curb.b - curb.a).norm();
  for (double x = uniform(rng, 4.0, 12.0); x < length - 4.0; x += uniform(rng, 8.0, 14.0)) {
    if (!chance(rng, std::min(0.95, 0.6 * density))) continue;
    const Vec2 at = curb.a + x * dir - 0.9 * out;
    const double h = uniform(rng, 5.0, 12.0);
    if (kept_clear(keep_clear, at)) {
      Mesh unused;  // the same draws, so that the rest of the street does not change
      add_tree(unused, rng, w.ground, at, h);
      continue;
    }
    add_tree(w.static_mesh, rng, w.ground, at, h);
    w.objects.push_back({"tree", 0, Vec3(at.x(), at.y(), 0.0), 0.0, {h * 0.4, h * 0.4, h}});
  }
  for (double x = uniform(rng, 5.0, 20.0); x < length - 3.0; x += uniform(rng, 22.0, 35.0)) {
    if (!chance(rng, std::min(1.0, 0.8 * density))) continue;
    const Vec2 at = curb.a + x * dir - 0.45 * out;
    const bool lamp = chance(rng, 0.7);
    const double h = lamp ? uniform(rng, 6.0, 8.0) : uniform(rng, 2.5, 3.5);
    if (kept_clear(keep_clear, at)) continue;
    add_pole(w.static_mesh, w.ground, at, h, lamp, std::atan2(out.y(), out.x()));
    w.objects.push_back({lamp ? "street_lamp" : "pole", 0, Vec3(at.x(), at.y(), 0.0), 0.0, {0.2, 0.2, h}});
  }
}

// Parked cars along one curb of a street segment: `a`-`b` on the parking line.
void add_parked_cars(World& w, Rng& rng, const Vec2& a, const Vec2& b, double density,
                     const std::vector<RaisedArea>& keep_clear) {
  const Vec2 dir = (b - a).normalized();
  const double length = (b - a).norm(), heading = std::atan2(dir.y(), dir.x());
  for (double x = uniform(rng, 0.0, 4.0); x < length - 6.5;) {
    const double slot = uniform(rng, 5.2, 7.0);
    if (chance(rng, std::min(0.95, 0.55 * density))) {
      Dimensions dims;
      const bool truck = chance(rng, 0.1);
      Mesh mesh = truck ? make_truck_mesh(rng, &dims) : make_car_mesh(rng, &dims);
      if (dims.length > slot - 0.6) {
        x += slot;
        continue;
      }
      const Vec2 at = a + (x + 0.5 * slot) * dir;
      const double yaw = heading + (chance(rng, 0.25) ? M_PI : 0.0) + uniform(rng, -0.03, 0.03);
      // A reserved slot stays empty; the draws above keep the rest of the street as it would be.
      if (kept_clear(keep_clear, at)) {
        x += slot;
        continue;
      }
      const std::uint32_t id = w.new_instance();
      const Label label = semantic::make(truck ? semantic::kOtherVehicle : semantic::kCar, id);
      for (auto& m : mesh.materials) m.label = label;
      const Pose pose = ground_pose(w.ground, {at, yaw}, 0.0, true);
      w.static_mesh.append(mesh, pose);
      w.objects.push_back({truck ? "parked_truck" : "parked_car", id, pose.translation(), yaw, dims});
    }
    x += slot;
  }
}
}  // namespace

void build_city(World& w, const CityLayout& city, Rng& rng, double density) {
  const double h = 0.5 * city.street;
  for (int i = 0; i < city.nx; ++i)
    for (int j = 0; j < city.ny; ++j) w.ground.raised.push_back(city.block_area(i, j));
  add_ground_grid(w.static_mesh, w.ground, city.street_x(0) - h - city.margin_x0, -h - kMargin,
                  city.street_x(city.nx) + h + city.margin_x1, city.street_y(city.ny) + h + kMargin, 4.0, 0.0,
                  [](double, double) {
                    return Material{cls::kRoad, 0.22f};
                  });
  for (const RaisedArea& r : w.ground.raised) {
    add_block_ground(w, r, city.sidewalk);
    for (const Side& s : sides_of(r, city.sidewalk)) add_lots(w, rng, city, s);
    for (const Side& s : sides_of(r, 0.0)) add_street_furniture(w, rng, s, density, city.keep_clear);
  }
  // Parked cars along both curbs of every street segment between intersections.
  const double skip = h + 5.0;
  for (int j = 0; j <= city.ny; ++j)
    for (int i = 0; i < city.nx; ++i)
      for (double side : {-1.0, 1.0}) {
        const double y = city.street_y(j) + side * kParkingOffset;
        add_parked_cars(w, rng, {city.street_x(i) + skip, y}, {city.street_x(i + 1) - skip, y}, density,
                        city.keep_clear);
      }
  for (int i = 0; i <= city.nx; ++i)
    for (int j = 0; j < city.ny; ++j)
      for (double side : {-1.0, 1.0}) {
        const double x = city.street_x(i) + side * kParkingOffset;
        add_parked_cars(w, rng, {x, city.street_y(j) + skip}, {x, city.street_y(j + 1) - skip}, density,
                        city.keep_clear);
      }
}

}  // namespace dloam::sim
