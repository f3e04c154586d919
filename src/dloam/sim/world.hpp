// A simulated world: static mesh (labelled per triangle), moving actors, the ego vehicle's motion
// and the ground. Built by the scenario generators (scenario.hpp), consumed by the Simulator.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "dloam/sim/actors.hpp"
#include "dloam/sim/ego.hpp"

namespace dloam::sim {

/// A static object, for the scenario description (parked cars carry an instance id).
struct StaticObject {
  std::string kind;  ///< "building", "tree", "pole", "parked_car", ...
  std::uint32_t instance = 0;
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  Dimensions dims;
};

struct World {
  std::string scenario;
  Ground ground;
  Mesh static_mesh;
  std::vector<Actor> actors;
  std::vector<StaticObject> objects;
  Ego ego;
  double frame_period = 0.1;  ///< one sweep (s)
  std::uint32_t next_instance = 1;

  /// A fresh instance id; ids live in the upper 16 bits of a label, so at most 65535 objects.
  std::uint32_t new_instance() {
    if (next_instance > 0xFFFFu) throw std::length_error("world: more than 65535 objects need instance ids");
    return next_instance++;
  }
};

}  // namespace dloam::sim
