// Actor classes, poses over time and stop-and-go speed profiles.
#include "dloam/sim/actors.hpp"

#include <stdexcept>

namespace dloam::sim {

std::string to_string(ActorKind kind) {
  switch (kind) {
    case ActorKind::Car:
      return "car";
    case ActorKind::Truck:
      return "truck";
    case ActorKind::Cyclist:
      return "cyclist";
    case ActorKind::Pedestrian:
      return "pedestrian";
  }
  return "unknown";
}

Label static_class(ActorKind kind) {
  switch (kind) {
    case ActorKind::Car:
      return semantic::kCar;
    case ActorKind::Truck:
      return semantic::kOtherVehicle;
    case ActorKind::Cyclist:
      return semantic::kBicyclist;
    case ActorKind::Pedestrian:
      return semantic::kPerson;
  }
  return semantic::kUnlabeled;
}

Label moving_class(ActorKind kind) {
  switch (kind) {
    case ActorKind::Car:
      return semantic::kMovingCar;
    case ActorKind::Truck:
      return semantic::kMovingOtherVehicle;
    case ActorKind::Cyclist:
      return semantic::kMovingBicyclist;
    case ActorKind::Pedestrian:
      return semantic::kMovingPerson;
  }
  return semantic::kUnlabeled;
}

Mesh make_actor_mesh(ActorKind kind, Rng& rng, Dimensions* dims) {
  switch (kind) {
    case ActorKind::Car:
      return make_car_mesh(rng, dims);
    case ActorKind::Truck:
      return make_truck_mesh(rng, dims);
    case ActorKind::Cyclist:
      return make_cyclist_mesh(rng, dims);
    case ActorKind::Pedestrian:
      return make_pedestrian_mesh(rng, dims);
  }
  throw std::invalid_argument("unknown actor kind");
}

Label Actor::label(double t) const {
  return semantic::make(moving(t) ? moving_class(kind) : static_class(kind), instance);
}

Pose Actor::pose(const Ground& ground, double t) const {
  const bool vehicle = kind == ActorKind::Car || kind == ActorKind::Truck;
  return ground_pose(ground, path.at(s0 + profile.distance(t)), 0.0, vehicle);
}

SpeedProfile stop_and_go_profile(Rng& rng, double v, double t_begin, double t_end, const StopAndGo& p,
                                 bool start_moving) {
  const double ramp = v / p.accel;
  std::vector<SpeedKey> keys;
  double t = t_begin;
  bool moving = start_moving;
  keys.push_back({t, moving ? v : 0.0});
  while (t < t_end) {
    t += moving ? uniform(rng, p.move_min, p.move_max) : uniform(rng, p.stop_min, p.stop_max);
    keys.push_back({t, moving ? v : 0.0});
    t += ramp;
    moving = !moving;
    keys.push_back({t, moving ? v : 0.0});
  }
  return SpeedProfile(std::move(keys));
}

}  // namespace dloam::sim
