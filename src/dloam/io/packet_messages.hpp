// The drivers' raw-packet messages of ROS 2 bags, decoded from CDR to the packets they carry:
// velodyne_msgs/msg/VelodyneScan, pandar_msgs/msg/PandarScan, nebula_msgs/msg/NebulaPackets and
// ouster_sensor_msgs/msg/PacketMsg (or the older ouster_msgs/msg/PacketMsg). The packets are
// byte ranges of the message buffer, so nothing is copied.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dloam::io {

/// One packet of a message: bytes [offset, offset + size) of the message buffer.
struct PacketSlice {
  std::size_t offset = 0, size = 0;
  double stamp = 0.0;  ///< s since the epoch: the packet's own stamp, else the message's
};

struct PacketMessage {
  double stamp = 0.0;  ///< header stamp (s), or the bag's log time for types without a header
  std::vector<PacketSlice> packets;
};

/// The message types decode_packet_message() reads.
const std::vector<std::string>& packet_message_types();
bool is_packet_message_type(const std::string& type);

/// Decodes one message of a packet type (CDR). `log_time` (s) stamps what carries no stamp of
/// its own. Throws InputError "<where>: ..." for another type, a damaged or short message.
PacketMessage decode_packet_message(const std::string& type, const std::uint8_t* data, std::size_t size,
                                    double log_time, const std::string& where);

}  // namespace dloam::io
