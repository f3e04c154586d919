// Spinning-LiDAR sensor model: beam elevations, beam origin heights, horizontal resolution,
// range limits; and the row of a point (paper eq. 4 with a per-beam table instead of R_vert).
#pragma once

#include <string>
#include <vector>

#include "dloam/core/enum_names.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// Which returns of a multi-return sensor are kept.
enum class ReturnMode {
  kStrongest,  ///< the strongest (a single-return stream: its only return)
  kLast,       ///< the last
  kFirst,      ///< the first (where the sensor reports it)
  kAll,        ///< every distinct return
};
constexpr std::array<EnumName<ReturnMode>, 4> enum_names(ReturnMode) {
  return {{{ReturnMode::kStrongest, "strongest"},
           {ReturnMode::kLast, "last"},
           {ReturnMode::kFirst, "first"},
           {ReturnMode::kAll, "all"}}};
}

struct SensorConfig {
  std::string preset = "HDL-64E";
  int N_scan = 64;          ///< number of beams (range-image rows)
  int Horizon_SCAN = 2048;  ///< range-image columns, 2*pi / R_horiz
  /// Beam elevations in degrees, bottom beam first (row 0). Empty: uniform between
  /// Pit_bottom and fov_top with R_vert = (fov_top - Pit_bottom) / (N_scan - 1).
  std::vector<double> beam_elevations_deg;
  /// Height (m) of each beam's origin above the sensor origin, bottom beam first (a Velodyne
  /// calibration's vert_offset_correction; KITTI's HDL-64E: about 0.12 m lower block, 0.20 m
  /// upper block). Empty: every beam starts at the origin. A near point then lies up to a few
  /// beams above its beam as seen from the origin; row_of_point accounts for it.
  std::vector<double> beam_vertical_offsets_m;
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
  /// Height (m) of beam `row`'s origin (0 without beam_vertical_offsets_m).
  [[nodiscard]] double beam_vertical_offset_m(int row) const;
  /// Row of a point: the beam whose cone (from its own origin) is nearest in elevation, or -1
  /// outside the vertical field of view. Builds a BeamLookup: use one for many points.
  [[nodiscard]] int row_of_point(const Vec3& p) const;
  /// Throws std::invalid_argument naming the field when the model is inconsistent.
  void validate() const;
};

/// Precomputed row search of a sensor for many points: the row bands (midpoints between beam
/// elevations) in tan(elevation), found by a bin table and searched from each beam's origin.
class BeamLookup {
 public:
  explicit BeamLookup(const SensorConfig& sensor);
  /// Row of p (see SensorConfig::row_of_point), -1 outside the vertical field of view.
  [[nodiscard]] int row(const Vec3& p) const;
  /// As row(), also the bracketing neighbour row: the one on the side of the beam the point is
  /// on (clamped to the image). False outside the field of view.
  bool locate(const Vec3& p, int& row, int& neighbour) const;

 private:
  /// Band of tangent t: -1 below the lowest row, rows_ above the highest.
  [[nodiscard]] int band(double t) const;
  int rows_ = 0;
  std::vector<double> bound_;  ///< rows_ + 1 band limits in tan(elevation), increasing
  std::vector<double> beam_tan_;
  std::vector<double> offset_;   ///< beam origin heights, empty when all 0
  std::vector<int> first_band_;  ///< band at the lower edge of equal bins of tan(elevation)
  double scale_ = 1.0;           ///< bins per unit of tan(elevation)
};

/// A built-in preset as `dloam config presets` lists it.
struct SensorPresetInfo {
  std::string name;
  std::string source;  ///< the model and where its numbers come from
  int beams = 0;
  double lowest_deg = 0.0, highest_deg = 0.0;
  int columns = 0;
};
/// The built-in presets (core/sensor_presets.cpp, one table of data), in table order.
std::vector<SensorPresetInfo> sensor_preset_info();
/// Their names, in table order.
std::vector<std::string> sensor_preset_names();
/// The names joined by `separator` (for help texts and error messages).
std::string sensor_preset_list(const std::string& separator = ", ");
/// A built-in preset (case-insensitive name); throws std::invalid_argument if unknown.
SensorConfig sensor_preset(const std::string& name);

}  // namespace dloam
