// Hesai decoder: Pandar40P, Pandar64, PandarQT64, PandarQT128 (C2X), PandarXT16, PandarXT32 and
// PandarXT32M (2X) point-cloud packets in, rotations out.
//
// Points: distance d = raw distance x the header's distance unit (Pandar40P: 4 mm); elevation el
// and azimuth offset from the angle-correction CSV; azimuth az = block azimuth + offset, clockwise
// from the sensor's 0 mark (its Y axis, the front). In Hesai's (and nebula's) frame x right,
// y front: (d cos el sin az, d cos el cos az, d sin el). dloam's frame (x front, y left, z up)
// rotates that by -90 deg about z: x = d cos el cos az, y = -d cos el sin az, z = d sin el.
//
// Returns of one firing (a group of `returns` blocks, from the return-mode byte) with
// ReturnMode::kAll, as nebula keeps them: a return is dropped when its raw distance is 0, when it
// lies outside the sensor's range or the configured one, or, unless it is the group's last block,
// when another return of the group is identical (distance and reflectivity) or closer than
// HesaiOptions::multi_return_separation_m. kFirst / kLast / kStrongest keep one return per firing:
// the block holding it in the packet's mode (dual last+strongest: block 0 last, block 1 strongest
// unless block 0 is, ...; the XT16/XT32 store first+last as last, first); a mode that does not
// report it gives the nearest (first), farthest (last) or most reflective (strongest) valid return.
// A single-return stream gives its only return whatever is asked. Point order: packet, block group,
// channel, return. return_id = the return's block within its group (its place in the mode's order).
//
// Scans are cut per channel (ChannelCut) at ScannerOptions::cut_azimuth_deg.
//
// Times: the sensors' clocks are not synchronised in general (the recordings here are dated 2017
// to 2120), so the time base is the recording stamp (Packet::stamp). Packet k is timed at
// sensor_time_k + offset, offset = the smallest (stamp - sensor time) of the last second of packets
// (StampAlignment): the sensor clock spaces the packets evenly, the stamps (receive times, which
// bunch after a stall) only place them. Each point adds its firing time relative to the packet's
// timestamp: the block group's offset and the channel's (hesai_model.hpp). Without stamps
// (Packet::stamp <= 0) the sensor's own times are used.
//
// Lost packets: gaps in the UDP sequence (or, for the Pandar40P, which has none, in the sensor
// time). Scans that lose packets are complete = false; a gap of a rotation or more ends the open
// scans and starts over. QT128 packets whose body or tail CRC does not match are not decoded
// (counted, and their scans are incomplete).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dloam/drivers/hesai_calibration.hpp"
#include "dloam/drivers/hesai_model.hpp"
#include "dloam/drivers/scanner.hpp"

namespace dloam::drivers {

struct HesaiOptions {
  /// Returns of one firing closer than this to another return of it are dropped, except the
  /// group's last (m; nebula's dual_return_distance_threshold).
  double multi_return_separation_m = 0.1;
  /// Adds the rotor's turn during each channel's firing-time offset (offset x motor speed) to
  /// its azimuth, as the user manuals' horizontal-angle formula does. Off: the CSV offset only, as
  /// nebula and Hesai's SDK without a firetime file.
  bool firing_time_azimuth = false;
};

/// True for a Hesai point-cloud data packet: an EE FF header, or the 1262-byte Pandar40P packet
/// of FF EE blocks. Not for GPS packets.
bool looks_like_hesai(const Packet& packet);

class HesaiScanner final : public Scanner {
 public:
  /// Throws InputError when `calibration` does not fit `model` (hesai::check_calibration).
  HesaiScanner(hesai::Model model, hesai::Calibration calibration, const ScannerOptions& scan,
               const HesaiOptions& options = {});
  ~HesaiScanner() override;
  HesaiScanner(const HesaiScanner&) = delete;
  HesaiScanner& operator=(const HesaiScanner&) = delete;

  void add(const Packet& packet, std::vector<Scan>& done) override;
  void finish(std::vector<Scan>& done) override;
  /// Beams sorted bottom first (ring = row), Horizon_SCAN = 360 deg / the most frequent azimuth
  /// step between firings (0.2 deg: 1800; the XT family's 0.18 deg: 2000; QT64 600; QT128 900;
  /// the model's step at 600 rpm before any packet), scan rate = motor speed / 60, range = the
  /// sensor's limits within the configured ones, preset = the model name.
  [[nodiscard]] SensorConfig sensor() const override;
  [[nodiscard]] std::string describe() const override;
  bool outline_only(bool on) override;
  [[nodiscard]] std::unique_ptr<Scanner> restart() const override;

  [[nodiscard]] hesai::Model model() const;
  [[nodiscard]] const hesai::Calibration& calibration() const;
  [[nodiscard]] std::size_t packets() const;          ///< data packets decoded
  [[nodiscard]] std::size_t lost_packets() const;     ///< missing from the UDP sequence (or time)
  [[nodiscard]] std::size_t ignored_packets() const;  ///< GPS packets
  [[nodiscard]] std::size_t corrupt_packets() const;  ///< CRC mismatch: not decoded
  [[nodiscard]] std::uint8_t return_mode() const;     ///< of the last data packet, 0 before any
  /// Ring (beam row, 0 = lowest) of each channel (0-based CSV order).
  [[nodiscard]] const std::vector<std::uint16_t>& rings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The scanner of a Hesai stream. Model: `options.model` (hesai::parse_model names) or, when
/// empty, the first data packet of `first_packets` (which are only inspected: feed them to add()
/// too); both given must agree. Calibration: `options.calibration` (angle-correction CSV), else
/// the model's nominal table. Throws InputError for an unknown model name, packets of an unknown
/// protocol, no data packet and no model, or a calibration that does not fit the model.
std::unique_ptr<Scanner> make_hesai_scanner(const DriverOptions& options,
                                            const std::vector<Packet>& first_packets);
std::unique_ptr<HesaiScanner> make_hesai_scanner(const DriverOptions& options,
                                                 const std::vector<Packet>& first_packets,
                                                 const HesaiOptions& hesai);

}  // namespace dloam::drivers
