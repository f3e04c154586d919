// Estimating a spinning LiDAR's sensor model from its scans alone (no calibration, no ring of the
// points, any point order): the beams, the height of each beam's origin, the image width, the
// range limits and the scan rate.
//
// Every return of beam k lies on its cone z = dz_k + h tan(e_k) (h: horizontal distance), i.e. in
// (u = 1/h, tau = z/h) on the line tau = tan(e_k) + dz_k u. Far points (u -> 0) give the beam's
// elevation whatever its origin height; near points give the height. The beams are found as modes
// of the elevation distribution, each elevation computed from the origin height that makes the
// distribution sharpest in its neighbourhood (the two laser blocks of an HDL-64E sit at different
// heights); then every point goes to its beam and each beam's (e, dz) is fitted robustly to its
// points, points no beam explains are searched for further beams, and the fit is repeated.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

struct SensorEstimationConfig {
  /// Added to the point elevations before anything else (SensorConfig's field of the same name;
  /// KITTI's HDL-64E needs 0.22 deg) and kept in the estimated model.
  double vertical_angle_correction_deg = 0.0;
  double max_offset_m = 0.3;         ///< beam origin heights searched within +-max_offset_m
  double min_horizontal_m = 0.1;     ///< points nearer the rotation axis are not used
  std::size_t max_points = 1000000;  ///< points fitted (a regular subsample of more)
};

struct EstimatedBeam {
  double elevation_deg = 0.0;   ///< e
  double offset_m = 0.0;        ///< dz, height of the beam's origin
  bool offset_measured = true;  ///< false: its points lie at too similar distances; dz of its neighbours
  double rms_deg = 0.0;         ///< elevation residual of its points (seen from its origin)
  std::size_t points = 0;       ///< points on the beam
};

struct SensorModelEstimate {
  SensorConfig sensor;               ///< preset "custom", validated
  std::vector<EstimatedBeam> beams;  ///< bottom first, one per row of `sensor`
  std::size_t scans = 0;
  std::size_t points = 0;           ///< input points
  std::size_t points_used = 0;      ///< beyond min_horizontal_m, after subsampling
  double on_beam_fraction = 0.0;    ///< of points_used, within its beam's residual band
  double azimuth_step_deg = 0.0;    ///< between neighbouring points of one beam
  bool scan_rate_measured = false;  ///< from the scan times; else 10 Hz is assumed
  std::vector<std::string> notes;   ///< what the estimate had to assume
};

/// Estimates the model from `scans` (sensor-frame points; several scans of a drive work best)
/// and `stamps` (the times of consecutive scans in seconds, may be empty: scan rate 10 Hz).
/// Throws InputError saying what is missing when the points cannot determine a model: too few
/// points, all points in one plane, fewer than 2 beams, or points that do not lie on beams (not
/// in the sensor frame).
SensorModelEstimate estimate_sensor_model(const std::vector<std::vector<Vec3>>& scans,
                                          const std::vector<double>& stamps,
                                          const SensorEstimationConfig& config = {});

/// How far a model's beam elevations are from a built-in preset's.
struct PresetMatch {
  std::string preset;
  double distance_deg = 0.0;  ///< mean distance of each beam to the nearest beam of the other, both ways
  int preset_beams = 0;
  bool resembles = false;  ///< same beam count and distance below a quarter of the median spacing
};
/// The nearest built-in preset.
PresetMatch nearest_preset(const SensorConfig& sensor);
/// The distance to a given preset (same measure).
PresetMatch match_preset(const SensorConfig& sensor, const std::string& preset);

}  // namespace dloam
