// Moving objects: cars, trucks, cyclists and pedestrians following a Path with a SpeedProfile.
// Their ground-truth label at time t is the moving class (252/253/254/259) when their speed
// exceeds 0.2 m/s, else the static class (10/31/30/20), with the instance id in the upper bits.
// Stop-and-go profiles make pseudo-static objects (standing, then moving, and vice versa).
#pragma once

#include <cstdint>
#include <string>

#include "dloam/sim/actor_meshes.hpp"
#include "dloam/sim/ground.hpp"
#include "dloam/sim/path.hpp"

namespace dloam::sim {

enum class ActorKind { Car, Truck, Cyclist, Pedestrian };

/// Speed above which an object counts as moving (SemanticKITTI moving classes).
inline constexpr double kMovingSpeed = 0.2;

std::string to_string(ActorKind kind);
Label static_class(ActorKind kind);  ///< 10 car, 20 other-vehicle, 31 bicyclist, 30 person
Label moving_class(ActorKind kind);  ///< 252, 259, 253, 254
Mesh make_actor_mesh(ActorKind kind, Rng& rng, Dimensions* dims);

struct Actor {
  ActorKind kind = ActorKind::Car;
  std::uint32_t instance = 0;  ///< unique per object, same in every frame
  Mesh mesh;                   ///< in the actor frame (x forward, z up, origin on the ground)
  Dimensions dims;
  Path path;
  SpeedProfile profile;
  double s0 = 0.0;  ///< arc length along the path at t = 0
  bool stop_and_go = false;
  std::string role;  ///< scripted objects: what they do (scenario.json); empty for road users
  /// The actor exists from t_begin to t_end (s); it appears and vanishes only out of sensor range.
  double t_begin = -1e9, t_end = 1e9;

  [[nodiscard]] bool present(double t) const { return t >= t_begin && t <= t_end; }

  [[nodiscard]] double speed(double t) const { return profile.speed(t); }
  [[nodiscard]] bool moving(double t) const { return speed(t) > kMovingSpeed; }
  [[nodiscard]] Label label(double t) const;
  /// Actor -> world at time t (s). Vehicles tilt with the terrain, people and cyclists stay upright.
  [[nodiscard]] Pose pose(const Ground& ground, double t) const;
};

/// Durations (s) and acceleration (m/s^2) of a stop-and-go pattern.
struct StopAndGo {
  double move_min = 3.0, move_max = 10.0;
  double stop_min = 2.0, stop_max = 6.0;
  double accel = 1.5;
};

/// Alternates cruising at `v` and standing still from `t_begin` to `t_end`, with random phase
/// durations, starting with a moving or a standing phase.
SpeedProfile stop_and_go_profile(Rng& rng, double v, double t_begin, double t_end, const StopAndGo& pattern,
                                 bool start_moving);

}  // namespace dloam::sim
