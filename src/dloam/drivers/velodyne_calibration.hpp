// Velodyne per-laser calibration: the ROS velodyne driver's calibration YAML (also nebula's), and
// VeloView's XML calibration (the db.xml layout), or a model's nominal table.
#pragma once

#include <string>
#include <vector>

#include "dloam/drivers/velodyne_model.hpp"

namespace dloam::drivers {

/// One laser, in the ROS driver's units: angles in radians, distances in metres.
struct VelodyneLaser {
  int laser_id = 0;
  double rot_correction = 0.0;   ///< azimuth correction (rad): corrected azimuth = azimuth - rot
  double vert_correction = 0.0;  ///< elevation (rad)
  double dist_correction = 0.0;  ///< added to every non-zero distance (m)
  double dist_correction_x = 0.0, dist_correction_y = 0.0;  ///< two-point correction (m)
  bool two_pt_correction_available = false;
  double vert_offset_correction = 0.0;             ///< height of the beam origin (m)
  double horiz_offset_correction = 0.0;            ///< horizontal offset of the beam origin (m)
  double focal_distance = 0.0, focal_slope = 0.0;  ///< intensity correction (HDL-64E)
  double min_intensity = 0.0, max_intensity = 255.0;
  int ring = 0;  ///< rank by elevation, 0 = lowest
};

struct VelodyneCalibration {
  std::vector<VelodyneLaser> lasers;  ///< indexed by laser_id
  /// distance_resolution of the file (m), 0 when the file has none. The packets' distance unit
  /// is a fact of the model (velodyne_model_info); a differing value is reported, not used.
  double distance_resolution = 0.0;
  std::string source;  ///< the file, or "nominal VLP-16 table"

  [[nodiscard]] int size() const { return static_cast<int>(lasers.size()); }
};

/// Reads a calibration file: ROS YAML (`lasers:` list with laser_id, rot_correction,
/// vert_correction, dist_correction, vert_offset_correction required; dist_correction_x/y,
/// two_pt_correction_available, horiz_offset_correction, focal_distance, focal_slope,
/// min_intensity, max_intensity optional; `num_lasers` and `distance_resolution` optional at the
/// top level, num_lasers checked against the list), or VeloView XML (`<DB>` with `points_` and
/// `enabled_`; degrees and centimetres, converted as the ROS driver's gen_calibration.py does).
/// Throws InputError naming the file and the key or entry that is wrong.
VelodyneCalibration read_velodyne_calibration(const std::string& path);

/// The model's nominal table (datasheet angles, no offsets). Throws InputError for the HDL-64E,
/// which has no usable nominal table.
VelodyneCalibration nominal_velodyne_calibration(VelodyneModel model);

/// Sets `ring` from the elevations (ties by laser id).
void assign_velodyne_rings(VelodyneCalibration& calibration);

}  // namespace dloam::drivers
