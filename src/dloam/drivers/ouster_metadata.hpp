// Ouster sensor metadata: the JSON a sensor serves (and ouster-sdk stores beside a recording) with
// the beam angles, the lidar mode, the UDP packet layout and the lidar / sensor transforms. Both
// layouts are read: the flat one of firmware 2.x (beam_altitude_angles, data_format, ... at the top
// level, down to the reduced file with only the angles and lidar_mode) and the nested one of
// later firmware (sensor_info, beam_intrinsics, lidar_intrinsics, lidar_data_format,
// config_params). Keys the file leaves out get the defaults ouster-sdk assumes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace dloam::drivers {

/// UDP lidar profiles (udp_profile_lidar): how a pixel of a column is laid out.
enum class OusterProfile {
  kLegacy,               ///< LEGACY: 12 B pixels, 16 B column header, 4 B column status
  kSingle,               ///< RNG19_RFL8_SIG16_NIR16: 12 B pixels
  kDual,                 ///< RNG19_RFL8_SIG16_NIR16_DUAL: 16 B pixels, two returns
  kLowDataRate,          ///< RNG15_RFL8_NIR8: 4 B pixels, range in 8 mm units
  kLowDataRateDual,      ///< RNG15_RFL8_NIR8_DUAL: 8 B pixels, two returns
  kFusaLowDataRateDual,  ///< FUSA_RNG15_RFL8_NIR8_DUAL: as above, functional-safety header
};

/// The name as the metadata writes it ("RNG15_RFL8_NIR8").
const char* to_string(OusterProfile profile);

/// Order of the two returns of a dual-return profile (config_params.return_order).
enum class OusterReturnOrder {
  kStrongestToWeakest,  ///< the default (and the only order before firmware 3): RANGE is the strongest
  kNearestToFarthest,
  kFarthestToNearest,
};

struct OusterMetadata {
  std::string source;          ///< the file (or a label), for messages
  bool nested_layout = false;  ///< sensor_info / beam_intrinsics / ... (false: the flat layout)

  std::string prod_line;      ///< "OS-1-128"; empty when the file does not say
  std::uint64_t prod_sn = 0;  ///< 0: unknown
  std::uint32_t init_id = 0;  ///< initialization_id; 0: unknown
  std::string firmware;       ///< "v2.3.0", from build_rev or image_rev; empty: unknown
  int firmware_major = -1;    ///< -1: unknown

  std::string lidar_mode;     ///< "1024x10"; empty when only lidar_data_format gives the size
  int columns_per_frame = 0;  ///< W
  double fps = 0.0;           ///< frames (rotations) per second
  int pixels_per_column = 0;  ///< H: beams
  int columns_per_packet = 16;
  int column_window_first = 0;  ///< first / last measurement_id the sensor sends (may wrap)
  int column_window_last = 0;
  /// Per row (Ouster's beam order, top beam first): the destaggered image column of a
  /// measurement is (measurement_id + shift) mod W.
  std::vector<int> pixel_shift_by_row;
  OusterProfile profile = OusterProfile::kLegacy;
  bool fusa_header = false;        ///< the functional-safety packet header (header_type FUSA)
  bool imu_profile_legacy = true;  ///< udp_profile_imu LEGACY: 48 B IMU packets
  /// 48 for LEGACY; ACCEL32_GYRO32_NMEA: 164 + 36 x imu_data_format.imu_measurements_per_packet,
  /// 0 when the file does not give the count (then any 164 + 36 k bytes is taken for IMU).
  int imu_packet_size = 48;
  OusterReturnOrder return_order = OusterReturnOrder::kStrongestToWeakest;
  int udp_port_lidar = 0, udp_port_imu = 0;  ///< 0: not in the file
  double min_range_threshold_m = -1.0;       ///< config_params.min_range_threshold_cm; < 0: absent

  /// Beam angles in degrees, Ouster's order (top beam first): H entries each.
  std::vector<double> beam_altitude_deg, beam_azimuth_deg;
  double lidar_origin_to_beam_origin_mm = 0.0;
  /// beam_to_lidar_transform (the nested layout's, or identity with x = the beam origin offset)
  /// and lidar_to_sensor_transform: 4x4, translation in mm.
  Eigen::Matrix4d beam_to_lidar = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d lidar_to_sensor = Eigen::Matrix4d::Identity();

  /// Measurement ids in the column window.
  [[nodiscard]] int window_columns() const;
  [[nodiscard]] bool in_window(int measurement_id) const;
  /// Whether the lidar packets carry a CRC-64 in their last 8 bytes: not LEGACY, not the FuSa
  /// header, firmware 3 or later. 0 = no, 1 = yes, -1 = unknown (firmware not in the file).
  [[nodiscard]] int crc_expected() const;
};

/// Parses metadata JSON text; `source` names it in messages. Throws dloam::InputError
/// "<source>: <key>: <problem>" for invalid JSON, a missing required key (the beam angles, the
/// lidar mode), a value of the wrong type or out of range, or keys that contradict each other.
OusterMetadata parse_ouster_metadata(const std::string& json_text, const std::string& source);
/// Reads and parses a metadata file (InputError when it cannot be read).
OusterMetadata load_ouster_metadata(const std::string& path);

}  // namespace dloam::drivers
