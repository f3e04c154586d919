// Scripted objects for map cleaning: pedestrians that stand then walk (and walk then stand), and a
// parked car that drives off, placed beside the ego's drive so that it sees them change.
#include <cmath>

#include "dloam/sim/city.hpp"

namespace dloam::sim {

namespace {
constexpr double kWalk = 1.4;       // m/s
constexpr double kWalkAccel = 1.0;  // m/s^2
constexpr double kDriveOff = 8.0;   // m/s
constexpr double kCarAccel = 2.0;   // m/s^2

Actor scripted(Rng& rng, ActorKind kind, const std::string& role, Path path, SpeedProfile profile,
               double s0) {
  Actor a;
  a.kind = kind;
  a.role = role;
  a.mesh = make_actor_mesh(kind, rng, &a.dims);
  a.path = std::move(path);
  a.profile = std::move(profile);
  a.s0 = s0;
  a.stop_and_go = true;  // pseudo-static: both states during the drive
  return a;
}
}  // namespace

std::vector<Actor> cleaning_actors(const Ego& ego, const CityLayout& city, int j, double duration,
                                   double t_leave, Rng& rng, std::vector<RaisedArea>* keep_clear) {
  const double yc = city.street_y(j), half = 0.5 * duration;
  const double x_mid = ego.position(half).x();
  const double sidewalk = 0.5 * city.street + 2.3;
  std::vector<Actor> out;
  {  // Stands on the right sidewalk until half the drive, then walks off along it.
    const Vec2 at(x_mid + 6.0, yc - sidewalk);
    keep_clear->push_back(
        {at.x() - 25.0, yc - 0.5 * city.street - 1.5, at.x() + 8.0, yc - kParkingOffset + 1.0, 0.0});
    out.push_back(scripted(rng, ActorKind::Pedestrian, "stand_then_walk",
                           Path::from_waypoints({at, at + Vec2(2000.0, 0.0)}, 0.0, false),
                           SpeedProfile({{half, 0.0}, {half + kWalk / kWalkAccel, kWalk}}), 0.0));
  }
  {  // Walks in on the left sidewalk against the ego's direction and stands from half the drive.
    const Vec2 at(x_mid - 4.0, yc + sidewalk);
    keep_clear->push_back(
        {at.x() - 25.0, yc + kParkingOffset - 1.0, at.x() + 8.0, yc + 0.5 * city.street + 1.5, 0.0});
    SpeedProfile profile({{half - kWalk / kWalkAccel, kWalk}, {half, 0.0}});
    const double s_stand = 2000.0;
    const double s0 = s_stand - profile.distance(half);
    out.push_back(scripted(rng, ActorKind::Pedestrian, "walk_then_stand",
                           Path::from_waypoints({at + Vec2(s_stand, 0.0), at}, 0.0, false),
                           std::move(profile), s0));
  }
  {  // Parked at the left curb facing -x, pulls out into the left lane at t_leave and drives off.
    const double x = ego.position(t_leave).x() + 18.0, yp = yc + kParkingOffset, yl = yc + kLaneOffset;
    const Path path =
        Path::from_waypoints({{x, yp}, {x - 5.0, yp}, {x - 12.0, yl}, {x - 2000.0, yl}}, 8.0, false, 3.0);
    out.push_back(scripted(rng, ActorKind::Car, "leaving_car", path,
                           SpeedProfile({{t_leave, 0.0}, {t_leave + kDriveOff / kCarAccel, kDriveOff}}),
                           0.0));
    keep_clear->push_back({x - 7.0, yp - 1.0, x + 7.0, yp + 1.0, 0.0});
  }
  return out;
}

}  // namespace dloam::sim
