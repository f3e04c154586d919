// Road-user meshes. Materials only carry reflectivity here: the label of an actor's points is
// decided per ray from its motion at the ray's time (see actors.hpp).
#include "dloam/sim/actor_meshes.hpp"

namespace dloam::sim {

namespace {
Material paint(Rng& rng) { return {semantic::kUnlabeled, static_cast<float>(uniform(rng, 0.08, 0.9))}; }
constexpr Material kTyre{semantic::kUnlabeled, 0.05f};
constexpr Material kGlass{semantic::kUnlabeled, 0.12f};

void add_wheels(Mesh& m, double wheelbase, double track, double radius) {
  for (double sx : {-0.5, 0.5})
    for (double sy : {-0.5, 0.5}) {
      const Vec3 c(sx * wheelbase, sy * track, radius);
      add_cylinder(m, c - Vec3(0, 0.12, 0), c + Vec3(0, 0.12, 0), radius, 10, kTyre);
    }
}
}  // namespace

Mesh make_car_mesh(Rng& rng, Dimensions* dims) {
  const double L = uniform(rng, 3.8, 4.9), W = uniform(rng, 1.7, 1.95), H = uniform(rng, 1.4, 1.65);
  Mesh m;
  const Material body = paint(rng);
  add_box_z(m, 0.0, 0.0, 0.0, L, W, 0.3, 0.95, body);                            // lower body
  add_box_z(m, L * 0.38, 0.0, 0.0, L * 0.2, W * 0.96, 0.95, 1.0, body);          // bonnet lip
  add_box_z(m, -L * 0.08, 0.0, 0.0, L * 0.5, W * 0.86, 0.95, H - 0.05, kGlass);  // cabin
  add_box_z(m, -L * 0.08, 0.0, 0.0, L * 0.46, W * 0.84, H - 0.05, H, body);      // roof
  add_wheels(m, L * 0.62, W - 0.2, 0.32);
  if (dims != nullptr) *dims = {L, W, H};
  return m;
}

Mesh make_truck_mesh(Rng& rng, Dimensions* dims) {
  const bool van = chance(rng, 0.5);
  const double L = van ? uniform(rng, 4.8, 6.0) : uniform(rng, 7.5, 12.0);
  const double W = van ? uniform(rng, 1.95, 2.1) : uniform(rng, 2.4, 2.55);
  const double H = van ? uniform(rng, 2.0, 2.6) : uniform(rng, 3.0, 3.8);
  Mesh m;
  const Material body = paint(rng);
  const double cab = van ? 0.0 : 2.2;
  if (van) {
    add_box_z(m, 0.0, 0.0, 0.0, L, W, 0.35, H, body);
    add_box_z(m, L * 0.5 - 0.05, 0.0, 0.0, 0.12, W * 0.9, 1.1, H - 0.3, kGlass);  // windscreen
  } else {
    add_box_z(m, 0.5 * L - 0.5 * cab, 0.0, 0.0, cab, W, 0.5, 2.9, body);             // cab
    add_box_z(m, -0.5 * cab - 0.1, 0.0, 0.0, L - cab - 0.3, W, 1.0, H, paint(rng));  // cargo box
    add_box_z(m, 0.0, 0.0, 0.0, L * 0.9, W * 0.6, 0.45, 1.0, kTyre);                 // chassis
  }
  add_wheels(m, L * 0.66, W - 0.25, van ? 0.36 : 0.5);
  if (dims != nullptr) *dims = {L, W, H};
  return m;
}

Mesh make_cyclist_mesh(Rng& rng, Dimensions* dims) {
  Mesh m;
  const Material frame{semantic::kUnlabeled, static_cast<float>(uniform(rng, 0.2, 0.8))};
  const Material cloth = paint(rng);
  const double r = 0.34;
  for (double x : {-0.52, 0.52}) add_cylinder(m, Vec3(x, -0.025, r), Vec3(x, 0.025, r), r, 12, kTyre);
  add_cylinder(m, Vec3(-0.52, 0, r), Vec3(0.0, 0, 0.85), 0.025, 5, frame);           // seat stay
  add_cylinder(m, Vec3(0.0, 0, 0.85), Vec3(0.45, 0, 0.95), 0.025, 5, frame);         // top tube
  add_cylinder(m, Vec3(0.52, 0, r), Vec3(0.45, 0, 1.05), 0.025, 5, frame);           // fork
  add_cylinder(m, Vec3(0.45, -0.28, 1.05), Vec3(0.45, 0.28, 1.05), 0.02, 5, frame);  // handlebar
  const double torso = uniform(rng, 0.55, 0.65);
  add_cylinder(m, Vec3(-0.05, 0, 0.95), Vec3(0.2, 0, 0.95 + torso), 0.16, 8, cloth);  // leaning torso
  add_ellipsoid(m, Vec3(0.26, 0, 1.08 + torso), Vec3(0.11, 0.1, 0.12), 1, cloth);     // head / helmet
  for (double y : {-0.1, 0.1}) {
    add_cylinder(m, Vec3(-0.02, y, 0.95), Vec3(0.05, y * 1.3, 0.45), 0.065, 6, cloth);        // legs
    add_cylinder(m, Vec3(0.2, y, 0.85 + torso), Vec3(0.43, y * 2.5, 1.06), 0.045, 6, cloth);  // arms
  }
  if (dims != nullptr) *dims = {1.8, 0.6, 1.2 + torso};
  return m;
}

Mesh make_pedestrian_mesh(Rng& rng, Dimensions* dims) {
  Mesh m;
  const double s = uniform(rng, 0.85, 1.08);  // body scale, about 1.5-1.9 m tall
  const Material cloth = paint(rng), skin{semantic::kUnlabeled, 0.3f};
  for (double y : {-0.1, 0.1}) add_cylinder(m, Vec3(0, y, 0), Vec3(0, y, 0.85 * s), 0.075 * s, 6, cloth);
  add_box_z(m, 0.0, 0.0, 0.0, 0.24 * s, 0.4 * s, 0.82 * s, 1.45 * s, cloth);  // torso
  for (double y : {-0.25, 0.25})
    add_cylinder(m, Vec3(0, y * s, 1.42 * s), Vec3(0.03, y * 1.1 * s, 0.8 * s), 0.045 * s, 6, cloth);  // arms
  add_cylinder(m, Vec3(0, 0, 1.45 * s), Vec3(0, 0, 1.55 * s), 0.05 * s, 6, skin);                      // neck
  add_ellipsoid(m, Vec3(0, 0, 1.64 * s), Vec3(0.1, 0.085, 0.12) * s, 1, skin);                         // head
  if (chance(rng, 0.3))
    add_box_z(m, -0.2 * s, 0.0, 0.0, 0.18, 0.32 * s, 1.0 * s, 1.45 * s, paint(rng));  // backpack
  if (dims != nullptr) *dims = {0.45 * s, 0.55 * s, 1.76 * s};
  return m;
}

}  // namespace dloam::sim
