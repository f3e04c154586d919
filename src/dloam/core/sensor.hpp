// Spinning-LiDAR sensor model: beam elevations, horizontal resolution, range limits.
#pragma once

#include <string>
#include <vector>

namespace dloam {

struct SensorConfig {
  std::string preset = "HDL-64E";
  int N_scan = 64;          ///< number of beams (range-image rows)
  int Horizon_SCAN = 2048;  ///< range-image columns, 2*pi / R_horiz
  /// Beam elevations in degrees, bottom beam first (row 0). Empty: uniform between
  /// Pit_bottom and fov_top with R_vert = (fov_top - Pit_bottom) / (N_scan - 1).
  std::vector<double> beam_elevations_deg;
  double Pit_bottom = -24.9;  ///< lowest beam pitch (deg), paper eq. 4
  double fov_top = 2.0;       ///< highest beam pitch (deg)
  double min_range = 2.5;     ///< points closer than this are dropped (ego vehicle)
  double max_range = 120.0;
  double scan_rate_hz = 10.0;
  /// Elevation correction (deg) applied to every point before anything else (see
  /// correct_vertical_angle); KITTI's HDL-64E scans need about 0.2-0.25 deg.
  double vertical_angle_correction_deg = 0.0;

  [[nodiscard]] double R_horiz_deg() const { return 360.0 / Horizon_SCAN; }
  /// Elevation (deg) of beam `row`.
  [[nodiscard]] double beam_elevation_deg(int row) const;
  /// Nearest beam row for an elevation (deg), or -1 when it is outside the vertical field
  /// of view by more than half a beam spacing.
  [[nodiscard]] int row_of_elevation(double elevation_deg) const;
  /// Throws std::invalid_argument naming the field when the model is inconsistent.
  void validate() const;
};

/// Names of the built-in presets: HDL-64E, HDL-32E, VLP-16, OS1-64, OS1-128.
std::vector<std::string> sensor_preset_names();
/// A built-in preset (case-insensitive name); throws std::invalid_argument if unknown.
SensorConfig sensor_preset(const std::string& name);

}  // namespace dloam
