// Fitting a spinning LiDAR's beam table from its own scans, for the range-image rows of eq. 4:
// per beam the elevation e and the height dz of its origin (a Velodyne calibration's
// vert_correction and vert_offset_correction). Needs scans stored ring by ring (KITTI .bin:
// each beam's full turn, one after the other); the ring of a point comes from the point order,
// and each ring's points give z = dz + h tan(e) (h: horizontal distance) by robust least squares.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// Ring of every point of a scan stored ring by ring: the azimuth is unwrapped along the point
/// order and each full turn from the first point's azimuth is one ring (points within 0.3 deg
/// before the end of a turn already count to the next: jitter at the turn). Ring 0 is the first
/// stored, whatever its elevation.
std::vector<int> rings_from_point_order(const std::vector<Vec3>& points);

/// Accumulates scans, then fits one beam per ring.
class BeamTableFit {
 public:
  /// `sensor` gives the beam count and the range limits of the points used.
  explicit BeamTableFit(const SensorConfig& sensor) : sensor_(sensor) {}
  /// Adds a scan (already corrected by the sensor's vertical_angle_correction_deg). Throws
  /// InputError naming `source` when the point order does not give N_scan rings.
  void add(const std::vector<Vec3>& points, const std::string& source);

  struct Beam {
    int ring = 0;                ///< index in the point order
    double elevation_deg = 0.0;  ///< e
    double offset_m = 0.0;       ///< dz
    double rms_m = 0.0;          ///< residual of z (inliers)
    std::size_t points = 0;      ///< points used (inliers)
  };
  /// The beams sorted bottom first. Throws InputError when a ring has too few points.
  [[nodiscard]] std::vector<Beam> fit() const;
  /// `sensor` with the fitted beam_elevations_deg and beam_vertical_offsets_m (rounded to
  /// 0.001 deg / 0.001 m), validated.
  [[nodiscard]] SensorConfig fitted_sensor() const;

 private:
  SensorConfig sensor_;
  std::vector<std::vector<float>> h_, z_;  ///< per ring
};

}  // namespace dloam
