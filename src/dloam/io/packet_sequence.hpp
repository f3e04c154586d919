// Raw-packet recordings (pcap captures, ROS 2 bags of the drivers' packet messages) as dloam
// sequences: the packets go through a vendor scanner (drivers/registry.hpp). Opening makes one
// indexing pass over every packet, with the scanner set to outlines only (Scanner::outline_only:
// no points decoded), and records, per scan, where decoding can resume (a rotation before it), its
// time and its point count; read_scan(i) then decodes only that stretch, with points. The sensor
// model comes from the scanner (Sequence::sensor).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dloam/drivers/scanner.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::io {

/// A position in a packet stream to resume from (opaque to all but the stream that made it).
struct PacketCheckpoint {
  std::uint64_t a = 0, b = 0;
  std::size_t packet = 0;  ///< index of the next packet
};

/// One pass over the packets of a recording.
class PacketStream {
 public:
  virtual ~PacketStream() = default;
  /// The next packet, valid until the next call; false at the end. Packet::where names it.
  virtual bool next(drivers::Packet& packet) = 0;
  /// Where the stream stands (before the next packet), when it can resume exactly there.
  [[nodiscard]] virtual std::optional<PacketCheckpoint> checkpoint() const = 0;
};

/// A recording that can be read from its start or from a checkpoint, as often as needed.
class PacketRecording {
 public:
  virtual ~PacketRecording() = default;
  [[nodiscard]] virtual std::unique_ptr<PacketStream> open(const PacketCheckpoint* from = nullptr) const = 0;
  /// The recording's file (or bag and topic), for messages.
  [[nodiscard]] virtual std::string name() const = 0;
  /// What was read besides the packets (pcap: ports, other traffic, fragments).
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// The UDP datagrams of a capture to destination `port` (0: every port).
std::shared_ptr<PacketRecording> pcap_recording(const std::string& path, std::uint16_t port);

class Bag;
/// The packets of a packet-message topic of a ROS 2 bag (packet_messages.hpp types).
std::shared_ptr<PacketRecording> bag_packet_recording(std::shared_ptr<const Bag> bag,
                                                      const std::string& topic, const std::string& type);

using ScannerFactory =
    std::function<std::unique_ptr<drivers::Scanner>(const std::vector<drivers::Packet>& first_packets)>;

/// How many packets from the start of a recording a scanner is made from, at most.
constexpr std::size_t kFirstPackets = 1000;
constexpr std::size_t kFirstPacketBytes = std::size_t{32} << 20;  ///< about

/// The first packets of a recording, kept with their bytes (what a scanner is made from).
struct FirstPackets {
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<drivers::Packet> packets;                ///< point into `bytes`
  std::vector<std::optional<PacketCheckpoint>> after;  ///< the stream's checkpoint after each
};
/// Up to `max_packets` (and about `max_bytes`) packets from the start of the recording.
FirstPackets first_packets(const PacketRecording& recording, std::size_t max_packets = kFirstPackets,
                           std::size_t max_bytes = kFirstPacketBytes);
/// As above, the next packets of an open stream, which then stands after them.
FirstPackets first_packets(PacketStream& stream, std::size_t max_packets = kFirstPackets,
                           std::size_t max_bytes = kFirstPacketBytes);

/// One scan of a decoded rotation as the pipeline takes it: xyz, intensity and per-point time.
/// The per-point time is the one place where scan stamps become the pipeline's sweep fraction:
/// (stamp - scan.start) * scan_rate_hz, clamped to [0, 1).
PointCloud to_point_cloud(const drivers::Scan& scan, double scan_rate_hz);
/// As above, moving the scan's points into the cloud.
PointCloud to_point_cloud(drivers::Scan&& scan, double scan_rate_hz);

/// Reads the whole recording once (the index: scan outlines, Scanner::outline_only) and returns
/// it as a sequence; `make_scanner` builds the indexing scanner from the first packets, and the
/// scanner of each decoding session when it cannot restart() (Scanner::restart). Incomplete
/// rotations (the head and tail of a recording, lost packets) are kept only when the recording
/// has no complete one. Throws InputError for a recording without packets, packets no scanner
/// decodes, a recording without a scan. `times` = scan start times, `sensor` = the scanner's model.
/// `note` (which calibration was used, ...) is added to the source's describe().
Sequence open_packet_sequence(std::shared_ptr<PacketRecording> recording, ScannerFactory make_scanner,
                              const std::string& note = {});

}  // namespace dloam::io
