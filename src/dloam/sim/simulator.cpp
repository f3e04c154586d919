// Per frame: actors within sensor range get their motion over the sweep, the rest are hidden,
// then the sweep is cast.
#include "dloam/sim/simulator.hpp"

namespace dloam::sim {

Simulator::Simulator(World world, LidarOptions options)
    : world_(std::move(world)), options_(std::move(options)) {
  options_.validate();
  world_.frame_period = 1.0 / options_.sensor.scan_rate_hz;  // one sweep per rotation
  std::vector<const Mesh*> meshes;
  meshes.reserve(world_.actors.size());
  for (const auto& a : world_.actors) meshes.push_back(&a.mesh);
  caster_ = std::make_unique<RayCaster>(world_.static_mesh, meshes);
}

Simulator::~Simulator() = default;

void Simulator::set_motions(int index) {
  const double t0 = index * world_.frame_period;
  const Vec3 sensor_mid = sensor_pose(index, 0.5).translation();
  std::vector<Pose> poses(RayCaster::kMotionSteps);
  for (std::size_t i = 0; i < world_.actors.size(); ++i) {
    const Actor& a = world_.actors[i];
    for (int k = 0; k < RayCaster::kMotionSteps; ++k)
      poses[static_cast<std::size_t>(k)] =
          a.pose(world_.ground, t0 + world_.frame_period * k / (RayCaster::kMotionSteps - 1));
    const double reach = options_.sensor.max_range + std::max(a.dims.length, a.dims.height) +
                         (poses.back().translation() - poses.front().translation()).norm();
    const double d0 = (poses.front().translation() - sensor_mid).norm();
    const double d1 = (poses.back().translation() - sensor_mid).norm();
    if (!a.present(t0 + 0.5 * world_.frame_period) || std::min(d0, d1) > reach + 10.0) {
      caster_->disable_actor(i);
    } else {
      caster_->set_actor_motion(i, poses);
    }
  }
  caster_->commit();
}

SimFrame Simulator::frame(int index) {
  set_motions(index);
  SimFrame f;
  f.index = index;
  f.stamp = index * world_.frame_period;
  f.pose = sensor_pose(index, 0.5);
  f.scan = sweep(world_, *caster_, options_, index);
  return f;
}

}  // namespace dloam::sim
