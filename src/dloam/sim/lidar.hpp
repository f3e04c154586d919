// Spinning-LiDAR sweep model with a rolling shutter: beam `row` of column c fires at sweep time
// tau = (c + 0.5) / Horizon_SCAN towards azimuth atan2(y, x) = pi - 2 pi tau (column 0 at the
// rear, clockwise seen from above, as in core/range_image.hpp), from the sensor pose at that
// instant, and sees every actor where it is at that instant. The point is returned in the
// sensor frame at its firing time (raw, motion-distorted, like KITTI raw), with Gaussian range
// noise, random dropouts and an intensity from reflectivity and incidence angle.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/sim/raycaster.hpp"
#include "dloam/sim/world.hpp"

namespace dloam::sim {

struct LidarOptions {
  SensorConfig sensor = sensor_preset("HDL-64E");
  double range_noise = 0.02;  ///< Gaussian range noise sigma (m)
  double dropout = 0.01;      ///< probability that a return is lost
  std::uint64_t seed = 1;     ///< seed of the noise streams
  /// Throws std::invalid_argument naming the bad value.
  void validate() const;
};

/// One sweep. Points are in firing order (column by column, bottom beam first).
struct Scan {
  PointCloud cloud;                 ///< xyz, intensity in [0, 1], time = tau of each point
  std::vector<Label> labels;        ///< SemanticKITTI label per point (class | instance << 16)
  std::vector<std::uint16_t> rows;  ///< beam of each point
};

/// Sweeps `frame` (absolute times [frame, frame + 1) * world.frame_period) through `caster`,
/// whose actor motions must already be set for this sweep.
Scan sweep(const World& world, const RayCaster& caster, const LidarOptions& options, int frame);

}  // namespace dloam::sim
