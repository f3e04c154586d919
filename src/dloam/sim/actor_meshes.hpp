// Low-poly meshes of road users in their own frame (x forward, y left, z up, origin on the ground
// at the footprint centre): cars, trucks/vans, cyclists and pedestrians, with random sizes.
#pragma once

#include "dloam/sim/mesh.hpp"

namespace dloam::sim {

/// Footprint of an object (for placement and the scenario description).
struct Dimensions {
  double length = 0.0, width = 0.0, height = 0.0;
};

Mesh make_car_mesh(Rng& rng, Dimensions* dims = nullptr);
/// Vans and trucks (SemanticKITTI other-vehicle / truck sized).
Mesh make_truck_mesh(Rng& rng, Dimensions* dims = nullptr);
/// A bicycle with its rider.
Mesh make_cyclist_mesh(Rng& rng, Dimensions* dims = nullptr);
Mesh make_pedestrian_mesh(Rng& rng, Dimensions* dims = nullptr);

}  // namespace dloam::sim
