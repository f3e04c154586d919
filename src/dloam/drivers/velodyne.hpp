// Velodyne decoder: 1206-byte data packets (12 blocks of 32 returns, TOH, return-mode and product
// bytes) of the VLP-16, VLP-32C, HDL-32E, HDL-64E S2/S3 and VLS-128 to points in the ROS frame
// (x forward, y left, z up), with the ROS driver's per-laser correction model, exact per-point
// firing times, single / dual returns, and rotations cut at an azimuth. 512-byte position packets
// (port 8308) are recognised and counted.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dloam/drivers/scanner.hpp"
#include "dloam/drivers/velodyne_calibration.hpp"
#include "dloam/drivers/velodyne_model.hpp"

namespace dloam::drivers {

/// Velodyne-specific options (beside ScannerOptions).
struct VelodyneOptions {
  /// Field of view kept, on the corrected azimuth (deg, the sensor's convention: clockwise from
  /// its 0 mark, azimuth = atan2(-y, x) in the ROS frame), bounds included. fov_min_deg >
  /// fov_max_deg wraps through 0 (e.g. 270 -> 90 keeps the front half). [0, 360] keeps all. Also
  /// tells the scan assembly where missing packets are expected (a sensor configured to send
  /// only part of the turn): gaps outside the window do not make a scan incomplete.
  double fov_min_deg = 0.0;
  double fov_max_deg = 360.0;
};

/// One decoded return and where it came from.
struct VelodyneReturn {
  Vec3 xyz = Vec3::Zero();  ///< ROS frame (m)
  double time = 0.0;        ///< absolute firing time (s)
  float range = 0.0f;       ///< distance after dist_correction (m)
  float intensity = 0.0f;   ///< reflectivity after the calibration's intensity correction
  std::uint16_t raw_distance = 0;
  std::uint16_t azimuth = 0;        ///< corrected azimuth (0.01 deg), as used for xyz
  std::uint16_t block_azimuth = 0;  ///< the firing group's azimuth field (0.01 deg)
  float azimuth_step = 0.0f;        ///< azimuth change to the next firing group (0.01 deg)
  float time_in_group_us = 0.0f;    ///< firing time after the group's first firing (µs)
  std::uint8_t reflectivity = 0;
  std::uint8_t block = 0;      ///< 0-11, the block the return was read from
  std::uint8_t channel = 0;    ///< 0-31 in the block
  std::uint8_t group = 0;      ///< firing group of the packet (blocks sharing an azimuth)
  std::uint16_t laser = 0;     ///< calibration index
  std::uint16_t ring = 0;      ///< rank by elevation, 0 = lowest
  std::uint8_t return_id = 0;  ///< 0 = only / nearer return, 1 = farther (dual, both kept)
  bool last = true;            ///< dual: read from the last-return block
};

/// What the decoder tells about a data packet.
struct VelodynePacketHeader {
  std::uint32_t toh_us = 0;  ///< µs since the top of the hour
  std::uint8_t return_mode = 0;
  std::uint8_t product = 0;
};

/// True for a 1206-byte data packet whose block flags are Velodyne bank flags (FF EE, FF DD,
/// FF CC, FF BB; a dual-return VLS-128 packet may fill its last 4 blocks otherwise).
bool looks_like_velodyne(const Packet& packet);
/// True for a 512-byte position (GPS / PPS) packet; on a known port only when it is 8308.
bool is_velodyne_position_packet(const Packet& packet);
VelodynePacketHeader velodyne_packet_header(const Packet& packet);

/// Model identified from data packets: block flags, then the TOH spacing between packets (per
/// return mode), the VLP-16's channel structure (channels c and c + 16 are the same laser, 55 µs
/// apart, so their ranges nearly agree) and the product byte (which the 2014 VLP-16 firmware sets
/// to the HDL-32E's 0x21, so it alone does not decide).
struct VelodyneIdentification {
  VelodyneModel model = VelodyneModel::kVLP16;
  std::string evidence;  ///< why, for describe() / error messages
};
/// Throws InputError naming the first packet when there is no data packet or nothing decides.
VelodyneIdentification identify_velodyne(const std::vector<Packet>& packets);

namespace detail {
class VelodyneScanner;
}

/// Packet-level decoder: bytes to returns, no scan assembly.
class VelodyneDecoder {
 public:
  /// Receives the decoded firing groups and returns of a packet, in packet order.
  struct Sink {
    virtual ~Sink() = default;
    /// Firing group `group` of the packet: its azimuth field and the time of its first firing.
    virtual void group(int group, std::uint16_t azimuth, double time) = 0;
    virtual void point(const VelodyneReturn& r) = 0;
  };

  /// Throws InputError when the calibration's laser count does not fit the model.
  VelodyneDecoder(VelodyneModel model, VelodyneCalibration calibration, const ScannerOptions& scan = {},
                  const VelodyneOptions& options = {});

  /// Decodes one data packet. `hour_start` is the absolute time (s) at which the packet's TOH
  /// counter (µs since the top of the hour) was 0: a return's time is hour_start + TOH + its
  /// firing offset. Throws InputError naming packet.where on a wrong size, block flag, azimuth or
  /// return mode.
  void decode(const Packet& packet, double hour_start, Sink& sink);
  /// All returns of the packet (convenience for tests and tools).
  std::vector<VelodyneReturn> decode(const Packet& packet, double hour_start);

  [[nodiscard]] VelodyneModel model() const { return model_; }
  [[nodiscard]] const VelodyneCalibration& calibration() const { return calibration_; }
  [[nodiscard]] double min_range() const { return min_range_; }
  [[nodiscard]] double max_range() const { return max_range_; }
  /// Firing sequences (columns) per packet for a return mode byte.
  [[nodiscard]] int firings_per_packet(std::uint8_t return_mode) const;
  /// Nominal time between two data packets (µs) for a return mode byte.
  [[nodiscard]] double packet_period_us(std::uint8_t return_mode) const;
  /// True when corrected azimuth `azimuth` (0.01 deg) is inside the field of view.
  [[nodiscard]] bool in_fov(int azimuth) const {
    if (fov_min_ <= fov_max_) return azimuth >= fov_min_ && azimuth <= fov_max_;
    return azimuth >= fov_min_ || azimuth <= fov_max_;
  }

 private:
  friend class detail::VelodyneScanner;
  /// decode() with the sink's type known: no virtual call per return.
  template <class S>
  void decode_packet(const Packet& packet, double hour_start, S& sink);
  template <class S>
  void emit(std::uint16_t raw, std::uint8_t refl, int block, int bank, int channel, int group,
            std::uint16_t azimuth, float step, double group_time, std::uint8_t return_id, bool last,
            S& sink) const;

  struct LaserTerms {
    double cos_vert, sin_vert, rot_units;  // rot_units: rot_correction in 0.01 deg
    double dist_corr, dist_corr_x, dist_corr_y, vert_off, horiz_off;
    double focal_offset, focal_slope, min_int, max_int;
    float dist_corr_f;
    bool two_pt, simple, clamp;  // simple: no offsets, no two-point correction
    std::uint16_t ring;
  };
  VelodyneModel model_;
  VelodyneModelInfo info_;
  VelodyneCalibration calibration_;
  ScannerOptions scan_;
  VelodyneOptions options_;
  double min_range_ = 0.0, max_range_ = 0.0;
  int fov_min_ = 0, fov_max_ = 36000;
  float unit_f_ = 0.002f;
  std::vector<LaserTerms> terms_;
  std::array<std::array<float, 32>, 4> offset_us_{};  // [bank][channel]
  std::array<std::array<double, 32>, 4> offset_s_{};
  std::array<std::array<float, 32>, 4> fraction_{};  // offset / group period, the azimuth share
  std::array<std::array<std::uint16_t, 32>, 4> laser_{};
  const float* trig_ = nullptr;  // cos, sin of every 0.01 deg (shared table)
  bool vlp16_ = false, full_fov_ = true;
  float period_f_ = 1.0f;
  float last_step_ = 0.0f;  // azimuth step of the previous packet's last group
};

/// A Velodyne Scanner (see make_velodyne_scanner).
std::unique_ptr<Scanner> make_velodyne_scanner(const DriverOptions& options,
                                               const std::vector<Packet>& first_packets);
/// As above, with the Velodyne options (field of view).
std::unique_ptr<Scanner> make_velodyne_scanner(const DriverOptions& options,
                                               const std::vector<Packet>& first_packets,
                                               const VelodyneOptions& velodyne);

}  // namespace dloam::drivers
