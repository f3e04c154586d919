// Published facts of the Velodyne models (user manuals / datasheets): laser counts, distance units,
// packet layout per model, firing timing and the nominal angle tables.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dloam::drivers {

enum class VelodyneModel { kVLP16, kVLP32C, kHDL32E, kHDL64E_S2, kHDL64E_S3, kVLS128 };

/// Block flags of the 1206-byte data packets (stored little-endian: bytes FF EE, FF DD, ...).
inline constexpr std::uint16_t kVelodyneBank1 = 0xEEFF;  ///< upper block / lasers 0-31
inline constexpr std::uint16_t kVelodyneBank2 = 0xDDFF;  ///< lower block / lasers 32-63
inline constexpr std::uint16_t kVelodyneBank3 = 0xCCFF;  ///< VLS-128 lasers 64-95
inline constexpr std::uint16_t kVelodyneBank4 = 0xBBFF;  ///< VLS-128 lasers 96-127

inline constexpr std::size_t kVelodyneDataPacketSize = 1206;
inline constexpr std::size_t kVelodynePositionPacketSize = 512;
inline constexpr std::uint16_t kVelodyneDataPort = 2368;
inline constexpr std::uint16_t kVelodynePositionPort = 8308;

/// Return-mode byte (packet byte 1204).
inline constexpr std::uint8_t kVelodyneStrongest = 0x37;
inline constexpr std::uint8_t kVelodyneLast = 0x38;
inline constexpr std::uint8_t kVelodyneDual = 0x39;

/// What the decoder needs to know about a model.
struct VelodyneModelInfo {
  VelodyneModel model;
  const char* name;         ///< "VLP-16", "VLP-32C", "HDL-32E", "HDL-64E S2", "HDL-64E S3", "VLS-128"
  int lasers;               ///< beams
  double distance_unit_m;   ///< one count of the packet's distance field
  double max_range_m;       ///< datasheet range
  double min_range_m;       ///< returns closer than this are not reliable (datasheet / blind zone)
  int blocks_per_group;     ///< single-return blocks that share one azimuth (one firing sequence)
  double group_period_us;   ///< time between two firing groups (single-return)
  double toh_to_first_us;   ///< time of the packet's first firing minus its TOH stamp
  bool has_nominal_table;   ///< false: a per-unit calibration file is required
  std::uint8_t product_id;  ///< packet byte 1205 (0: the model has no product byte)
};

const VelodyneModelInfo& velodyne_model_info(VelodyneModel model);
const char* velodyne_model_name(VelodyneModel model);
/// Accepts the vendor's and the ROS drivers' spellings, case- and separator-insensitive:
/// "VLP-16" / "VLP16", "VLP-32C" / "VLP32" / "32C", "HDL-32E" / "HDL32" / "32E", "HDL-64E S2" /
/// "HDL64e_s2" / "64E_S2", "HDL-64E S3" / "64E_S3", "VLS-128" / "VLS128" / "VLP-128".
std::optional<VelodyneModel> parse_velodyne_model(const std::string& name);
/// Names accepted by parse_velodyne_model, for error messages.
std::string velodyne_model_names();

/// Firing time of one return relative to the first firing of its packet's firing group (µs),
/// and the fraction of the group period it corresponds to, as the manuals' timing tables give
/// them. `bank` is the block's laser bank (0-3: flags EE, DD, CC, BB), `channel` 0-31 its slot.
float velodyne_channel_offset_us(VelodyneModel model, int bank, int channel);
/// Laser (calibration index) of a block slot.
int velodyne_laser_of(VelodyneModel model, int bank, int channel);

/// Nominal angle table of a model (degrees): vertical angle and azimuth correction per laser,
/// in the ROS calibration's sign convention (the corrected azimuth is azimuth - rot).
/// Empty for the HDL-64E (every unit has its own calibration).
struct NominalAngles {
  std::vector<double> vert_deg;
  std::vector<double> rot_deg;
};
NominalAngles velodyne_nominal_angles(VelodyneModel model);

}  // namespace dloam::drivers
