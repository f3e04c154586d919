// Embree 3 ray caster of a world with moving objects. The static mesh and every actor mesh are
// their own Embree scenes, instanced in a top-level scene; each actor instance carries
// kMotionSteps transforms spread over the sweep (Embree multi-segment motion blur), so a ray
// with time tau in [0, 1] sees every actor where it is at that instant of the sweep.
// Embree stays hidden behind this interface (dloam_sim links it privately).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dloam/sim/mesh.hpp"

namespace dloam::sim {

class RayCaster {
 public:
  /// Transforms per actor per sweep (times k / (kMotionSteps - 1) of the sweep).
  static constexpr int kMotionSteps = 11;

  struct Hit {
    float range = -1.0f;  ///< distance along the (unit) ray; negative: no hit
    int actor = -1;       ///< index of the actor hit, -1 for the static scene
    std::uint32_t primitive = 0;
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();  ///< geometric normal in the hit mesh's frame
    [[nodiscard]] bool valid() const { return range >= 0.0f; }
  };

  /// Throws std::runtime_error when Embree reports an error.
  RayCaster(const Mesh& static_mesh, const std::vector<const Mesh*>& actor_meshes);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Motion of an actor over the coming sweep: exactly kMotionSteps actor->world poses.
  void set_actor_motion(std::size_t actor, const std::vector<Pose>& poses);
  /// Hides an actor (far away) until its next set_actor_motion().
  void disable_actor(std::size_t actor);
  /// Rebuilds the top-level scene; call after changing motions and before casting.
  void commit();

  /// Nearest hit along origin + r * direction (unit), r in [tnear, tfar], at sweep time tau.
  /// Thread-safe between commits.
  [[nodiscard]] Hit cast(const Vec3& origin, const Vec3& direction, float tau, float tnear, float tfar) const;
  /// Up to kPacket rays at one time, traced as an Embree packet (faster for the coherent beams of
  /// one column); hits[i] for the ray from origins[i] along directions[i].
  static constexpr int kPacket = 16;
  void cast_packet(const Vec3* origins, const Vec3* directions, int count, float tau, float tnear, float tfar,
                   Hit* hits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dloam::sim
