// The simulator: a World (scenario.hpp) swept by a rolling-shutter LiDAR (lidar.hpp) frame by
// frame. Ground truth per frame: labels per point and the sensor pose at the middle of the sweep;
// sensor_pose() gives the pose at any instant (for de-skewing).
#pragma once

#include <memory>

#include "dloam/sim/lidar.hpp"
#include "dloam/sim/world.hpp"

namespace dloam::sim {

struct SimFrame {
  int index = 0;
  double stamp = 0.0;            ///< start of the sweep (s)
  Pose pose = Pose::Identity();  ///< sensor -> world at the middle of the sweep (tau = 0.5)
  Scan scan;
};

class Simulator {
 public:
  /// The sweep period becomes 1 / options.sensor.scan_rate_hz. Throws std::invalid_argument for
  /// bad options.
  Simulator(World world, LidarOptions options);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// Sweep number `index` (any order; each call is independent and deterministic).
  SimFrame frame(int index);
  /// Sensor -> world at absolute time t (s).
  [[nodiscard]] Pose sensor_pose(double t) const { return world_.ego.sensor_pose(world_.ground, t); }
  /// Sensor -> world at sweep time tau in [0, 1] of frame `index`.
  [[nodiscard]] Pose sensor_pose(int index, double tau) const {
    return sensor_pose((index + tau) * world_.frame_period);
  }
  [[nodiscard]] const World& world() const { return world_; }
  [[nodiscard]] const LidarOptions& options() const { return options_; }

 private:
  void set_motions(int index);

  World world_;
  LidarOptions options_;
  std::unique_ptr<RayCaster> caster_;
};

}  // namespace dloam::sim
