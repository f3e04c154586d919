// Raw LiDAR packets in, scans out: the interface every vendor decoder (Velodyne, Ouster, Hesai)
// implements. A Scanner is fed the packets of one sensor in recording order, whatever the
// container (pcap, rosbag2 .db3 / MCAP, ROS 1 bag); it decodes each packet with the sensor's
// calibration / metadata, assembles full rotations and hands out finished scans. Pure bytes ->
// points: no file access (calibration files are parsed by the vendor's own reader).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam::drivers {

/// One UDP payload of the sensor, as recorded.
struct Packet {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  /// Recording time (s since the epoch): the pcap record time, or the packet's stamp in a bag
  /// message. Sensors whose clocks are not synchronised are timed from it.
  double stamp = 0.0;
  std::uint16_t port = 0;  ///< UDP destination port; 0 when unknown (packets from a bag)
  /// Where the packet came from, for error messages ("drive.pcap: packet 1207").
  std::string where;
};

/// Which returns of a multi-return sensor are kept (declared with the sensor model).
using ReturnMode = dloam::ReturnMode;

struct ScannerOptions {
  ReturnMode returns = ReturnMode::kStrongest;
  /// A scan ends where the azimuth crosses this angle (deg, the sensor's own azimuth convention,
  /// clockwise from its 0 mark). Ouster scans are its frames (frame_id), not cut by azimuth.
  double cut_azimuth_deg = 0.0;
  /// Returns closer / farther than this are dropped (m); <= 0: the sensor's own limits.
  double min_range = 0.0;
  double max_range = 0.0;
};

/// What a vendor's scanner is made from (`make_velodyne_scanner`, `make_ouster_scanner`,
/// `make_hesai_scanner`, each beside a `looks_like_<vendor>(const Packet&)` that tells the vendor's
/// data packets by size and magic).
struct DriverOptions {
  /// Model name as the vendor writes it ("VLP-16", "OS-1-128", "PandarXT32"); empty: from the packets.
  std::string model;
  /// Calibration file: the ROS velodyne driver's calibration YAML, Ouster's sensor metadata JSON,
  /// Hesai's angle-correction CSV. Empty: the model's built-in nominal table (an Ouster stream
  /// cannot be decoded without its JSON).
  std::string calibration;
  ScannerOptions scan;
};

/// The returns of one rotation, in decoding order (packet, firing, channel, return).
struct Scan {
  /// Sensor frame: x forward, y left, z up (ROS REP 103), metres, at each point's firing time.
  std::vector<Vec3> xyz;
  std::vector<float> intensity;                   ///< reflectivity / intensity as the sensor reports it
  std::vector<std::uint16_t> ring;                ///< beam, 0 = lowest elevation (a SensorConfig row)
  std::vector<std::uint8_t> return_id;            ///< 0 = first / only return, 1 = second, ...
  std::vector<double> stamps;                     ///< absolute firing time of each point (s)
  double start = 0.0;                             ///< time of the first firing of the rotation (s)
  double end = 0.0;                               ///< time of the last firing (s)
  std::size_t first_packet = 0, last_packet = 0;  ///< packet indices (Packet::where's counter)
  bool complete = true;  ///< a full rotation (false: partial head/tail of a recording, lost packets)
  /// From a scanner set to outlines only (Scanner::outline_only): the points the scan has; its
  /// point arrays are then empty. 0 otherwise.
  std::size_t outline_points = 0;

  [[nodiscard]] std::size_t size() const { return xyz.size(); }
  /// Every point array to `n` points (sized once before a decoder writes through them, cut back
  /// after).
  void resize_points(std::size_t n) {
    xyz.resize(n);
    intensity.resize(n);
    ring.resize(n);
    return_id.resize(n);
    stamps.resize(n);
  }
  /// For a decoder that writes points in place, `written` of them so far: the arrays at least
  /// `room` points longer than that, grown a chunk (8192 points, or `room`) at a time.
  void make_room(std::size_t written, std::size_t room) {
    constexpr std::size_t kChunk = 8192;
    if (xyz.size() < written + room) resize_points(written + std::max(kChunk, room));
  }
};

class Scanner {
 public:
  virtual ~Scanner() = default;
  /// Decodes one packet; scans it completes are appended to `done`. Throws dloam::InputError
  /// naming `packet.where` when the packet is not one of this sensor's (size, magic, model).
  /// Packets of other kinds the sensor sends on the same stream (position / IMU) are ignored
  /// and counted.
  virtual void add(const Packet& packet, std::vector<Scan>& done) = 0;
  /// End of the recording: the partial last rotation, when it has points.
  virtual void finish(std::vector<Scan>& done) = 0;
  /// The sensor model from the calibration / metadata and the packets seen so far: beam table
  /// (bottom beam first, elevations and origin heights), columns per rotation, range limits,
  /// scan rate.
  [[nodiscard]] virtual SensorConfig sensor() const = 0;
  /// One line for `dloam check` / `dloam run`: model, return mode, rpm, packets ignored.
  [[nodiscard]] virtual std::string describe() const = 0;

  /// Outlines only (on): the scans handed out have their start, end, packets and completeness,
  /// and count their points in Scan::outline_points without decoding them (no point arrays), as
  /// they would come out of the same packets with points; all that indexing a recording needs, for
  /// a fraction of the decoding. Set before the first packet. Returns whether the scanner does it
  /// (the default does not: it keeps handing out the points).
  virtual bool outline_only(bool on) { return !on; }
  /// A scanner as this one was made (no packet seen, scans with points), sharing its calibration
  /// and lookup tables: decoding again from the start or from a checkpoint. nullptr (the
  /// default) when the scanner cannot: then make a new one.
  [[nodiscard]] virtual std::unique_ptr<Scanner> restart() const { return nullptr; }
};

}  // namespace dloam::drivers
