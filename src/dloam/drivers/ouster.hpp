// Ouster OS0 / OS1 / OS2 decoder: lidar packets of any of the supported UDP profiles plus the
// sensor's metadata JSON in, one scan per Ouster frame (frame_id) out.
//
// - Frames: a scan is one frame; it is complete when every measurement id of the metadata's
//   column window arrived with its valid bit set. Lost packets, the partial first / last frame
//   of a recording and invalid columns give complete = false. Stragglers of a finished frame are
//   dropped and counted.
// - Points: the published XYZ model (ouster_geometry.hpp) in the sensor frame, x forward, y
//   left, z up. Returns with range 0 (no detection) or outside [min_range, max_range] are left
//   out. Order: measurement_id (firing order), then pixel (Ouster's beam order, top first), then
//   return. `ring` is the beam's row counted from the lowest beam; intensity is REFLECTIVITY.
// - Dual-return profiles (the two returns are RANGE / RANGE2): kStrongest keeps the strongest
//   (RANGE under the default STRONGEST_TO_WEAKEST return order; otherwise the return with the
//   higher SIGNAL, or REFLECTIVITY where the profile has no signal), kFirst the nearer, kLast the
//   farther, kAll both when they differ. return_id is the rank in range: 0 the nearer (or
//   only) return, 1 the farther.
// - Times: each point gets its column's timestamp (ns, sensor clock). When the packets have
//   recording times and the sensor clock is within 10 s of them (PTP / GPS time), the sensor
//   times are used as they are. Otherwise (the internal oscillator counts from power-up) they are
//   offset by one constant that puts the first lidar packet's last column at that packet's
//   recording time, re-anchored if they drift more than 1 s apart. So a scan keeps the sensor's
//   exact column spacing. Packets without a recording time (stamp 0) keep the sensor times.
// - CRC-64: looked for where the firmware may write it (not LEGACY, not the FuSa header, not
//   firmware 2.x). From the first packet whose stored CRC matches, the stream is known to carry
//   them and every packet is checked; a packet with a bad CRC is then dropped and counted
//   (describe(), stats()).
// - sensor(): the beam table bottom beam first, W columns, the frame rate, the product line's
//   range limits, and per beam the height from which its cone is seen in the sensor frame (the
//   lidar's mid-plane above the sensor base, less n cos(azimuth) tan(elevation) for the beam
//   origin offset n: OusterXyzLut::row_origin_heights), so that BeamLookup puts each point on
//   its own row.
// - IMU packets are ignored and counted: 48 B with the LEGACY IMU profile; with
//   ACCEL32_GYRO32_NMEA, 164 + 36 x imu_measurements_per_packet bytes (any 164 + 36 k when the
//   metadata does not give the count); and anything on the metadata's IMU port. Any other packet
//   is an error naming it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dloam/drivers/ouster_frame.hpp"
#include "dloam/drivers/ouster_geometry.hpp"
#include "dloam/drivers/ouster_metadata.hpp"
#include "dloam/drivers/ouster_profiles.hpp"
#include "dloam/drivers/scanner.hpp"

namespace dloam::drivers {

/// Whether a UDP payload is an Ouster lidar packet, from its size and structure alone (any
/// supported profile, 8-128 beams, 16 columns per packet): consecutive measurement ids of a
/// valid frame position and, for the non-LEGACY profiles, packet type 1.
bool looks_like_ouster(const Packet& packet);

/// The scanner for `options.calibration`, the sensor's metadata JSON (required: InputError
/// when it is empty, unreadable or invalid). `first_packets` are checked against it (packet size
/// vs profile and pixels, serial number and initialization id where the packets carry them), so
/// a metadata file of another sensor or configuration is reported at once, naming the file and
/// the packet.
std::unique_ptr<Scanner> make_ouster_scanner(const DriverOptions& options,
                                             const std::vector<Packet>& first_packets);

struct OusterStats {
  std::size_t lidar_packets = 0;             ///< decoded
  std::size_t imu_packets = 0;               ///< ignored
  std::size_t late_packets = 0;              ///< dropped: a frame that had already been finished
  std::size_t invalid_columns = 0;           ///< columns with the valid bit clear
  std::size_t crc_checked = 0, crc_bad = 0;  ///< bad ones are dropped
  std::size_t frames = 0, complete_frames = 0;
  std::size_t clock_reanchors = 0;
};

class OusterScanner : public Scanner {
 public:
  /// `lut`: the metadata's xyz lookup table when it is already built (restart() shares it);
  /// nullptr: built here.
  OusterScanner(OusterMetadata metadata, const DriverOptions& options,
                std::shared_ptr<const OusterXyzLut> lut = nullptr);

  void add(const Packet& packet, std::vector<Scan>& done) override;
  void finish(std::vector<Scan>& done) override;
  [[nodiscard]] SensorConfig sensor() const override;
  [[nodiscard]] std::string describe() const override;
  bool outline_only(bool on) override;
  [[nodiscard]] std::unique_ptr<Scanner> restart() const override;

  /// Throws InputError naming the packet and the metadata file when the packet is neither one
  /// of this stream's lidar packets nor an IMU packet. Returns true for a lidar packet.
  bool check(const Packet& packet) const;
  /// As check(); `fallback_index` numbers the packet when its `where` carries no index.
  bool check(const Packet& packet, std::size_t fallback_index) const;

  [[nodiscard]] const OusterMetadata& metadata() const { return md_; }
  [[nodiscard]] const OusterPacketFormat& format() const { return format_; }
  [[nodiscard]] const OusterXyzLut& lut() const { return *lut_; }
  [[nodiscard]] OusterStats stats() const;
  /// Frames as assembled, before the conversion to points (the raw fields of each scan handed
  /// out). Off by default; when on, they are kept until taken.
  void keep_frames(bool on) { keep_frames_ = on; }
  std::vector<OusterFrame> take_frames() { return std::move(kept_); }

 private:
  /// The frame's scan; kPoints false: its outline (the points counted, not computed).
  template <bool kPoints>
  void convert(OusterFrame& frame, std::vector<Scan>& done);
  void convert(OusterFrame& frame, std::vector<Scan>& done);
  void update_clock(const Packet& packet, std::uint64_t sensor_ns);

  OusterMetadata md_;
  DriverOptions options_;
  OusterPacketFormat format_;
  std::shared_ptr<const OusterXyzLut> lut_;
  OusterFrameBatcher batcher_;
  std::vector<std::uint16_t> ring_of_row_;  ///< Ouster row -> ring (0 = lowest beam)
  std::string preset_;
  double min_mm_ = 0.0, max_mm_ = 0.0;
  int crc_mode_ = -1;  ///< 1 check, 0 none, -1 decide on the first lidar packet
  std::size_t packets_seen_ = 0;
  OusterStats stats_;
  bool clock_set_ = false;
  double clock_offset_ = 0.0;
  bool keep_frames_ = false;
  bool outline_ = false;
  std::vector<OusterFrame> kept_;
};

/// Nominal range limits (m) of a product line ("OS-0-...", "OS-1-...", "OS-2-..."): the minimum
/// and maximum detection range of Ouster's data sheets.
void ouster_range_limits(const std::string& prod_line, double& min_range, double& max_range);

}  // namespace dloam::drivers
