// Raw-packet messages of ROS 2 bags (see packet_messages.hpp). Layouts (ROS 2 .msg files):
//   VelodyneScan  = std_msgs/Header header, VelodynePacket[] packets
//   VelodynePacket = builtin_interfaces/Time stamp, uint8[1206] data
//   PandarScan    = std_msgs/Header header, PandarPacket[] packets
//   PandarPacket  = builtin_interfaces/Time stamp, uint8[1500] data, uint32 size (valid bytes)
//   NebulaPackets = std_msgs/Header header, NebulaPacket[] packets
//   NebulaPacket  = builtin_interfaces/Time stamp, uint8[] data
//   PacketMsg (Ouster) = uint8[] buf; newer releases put a std_msgs/Header header first.
#include "dloam/io/packet_messages.hpp"

#include <algorithm>

#include "dloam/core/types.hpp"
#include "dloam/io/cdr.hpp"

namespace dloam::io {

namespace {
constexpr const char* kVelodyneScan = "velodyne_msgs/msg/VelodyneScan";
constexpr const char* kPandarScan = "pandar_msgs/msg/PandarScan";
constexpr const char* kNebulaPackets = "nebula_msgs/msg/NebulaPackets";
constexpr const char* kOusterPacket = "ouster_sensor_msgs/msg/PacketMsg";
constexpr const char* kOusterPacketOld = "ouster_msgs/msg/PacketMsg";

double read_time(CdrReader& r, const char* field) {
  const std::int32_t sec = r.i32(field);
  const std::uint32_t nsec = r.u32(field);
  return static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
}

/// std_msgs/Header: stamp, frame_id.
double read_header(CdrReader& r) {
  const double stamp = read_time(r, "header.stamp");
  (void)r.string("header.frame_id");
  return stamp;
}

std::size_t offset_of(const std::uint8_t* base, const std::uint8_t* p) {
  return static_cast<std::size_t>(p - base);
}

/// Ouster PacketMsg: `uint8[] buf` alone, or after a header. The form whose fields end where the
/// message ends (CDR may pad to 4 bytes) is the one written.
PacketMessage decode_ouster(const std::uint8_t* data, std::size_t size, double log_time,
                            const std::string& where) {
  PacketMessage m;
  {
    CdrReader r(data, size, where);
    if (r.remaining() >= 4) {
      std::size_t n = 0;
      const std::uint32_t announced = r.u32("buf");
      if (announced <= r.remaining() && r.remaining() - announced < 4) {
        r = CdrReader(data, size, where);
        const std::uint8_t* p = r.byte_sequence(n, "buf");
        m.stamp = log_time;
        m.packets.push_back({offset_of(data, p), n, log_time});
        return m;
      }
    }
  }
  CdrReader r(data, size, where);
  m.stamp = read_header(r);
  std::size_t n = 0;
  const std::uint8_t* p = r.byte_sequence(n, "buf");
  if (r.remaining() >= 4)
    r.fail("has " + std::to_string(r.remaining()) + " bytes after its fields: not an Ouster PacketMsg");
  m.packets.push_back({offset_of(data, p), n, m.stamp != 0.0 ? m.stamp : log_time});
  return m;
}
}  // namespace

const std::vector<std::string>& packet_message_types() {
  static const std::vector<std::string> types = {kVelodyneScan, kPandarScan, kNebulaPackets, kOusterPacket,
                                                 kOusterPacketOld};
  return types;
}

bool is_packet_message_type(const std::string& type) {
  const auto& t = packet_message_types();
  return std::find(t.begin(), t.end(), type) != t.end();
}

PacketMessage decode_packet_message(const std::string& type, const std::uint8_t* data, std::size_t size,
                                    double log_time, const std::string& where) {
  if (type == kOusterPacket || type == kOusterPacketOld) return decode_ouster(data, size, log_time, where);
  CdrReader r(data, size, where);
  PacketMessage m;
  if (type == kVelodyneScan) {
    m.stamp = read_header(r);
    const std::uint32_t n = r.sequence_count(8 + 1206, "packets");
    m.packets.reserve(n);
    for (std::uint32_t k = 0; k < n; ++k) {
      const double stamp = read_time(r, "packets[].stamp");
      const std::uint8_t* p = r.bytes(1206, "packets[].data");
      m.packets.push_back({offset_of(data, p), 1206, stamp});
    }
  } else if (type == kPandarScan) {
    m.stamp = read_header(r);
    const std::uint32_t n = r.sequence_count(8 + 1500 + 4, "packets");
    m.packets.reserve(n);
    for (std::uint32_t k = 0; k < n; ++k) {
      const double stamp = read_time(r, "packets[].stamp");
      const std::uint8_t* p = r.bytes(1500, "packets[].data");
      const std::uint32_t valid = r.u32("packets[].size");
      if (valid > 1500)
        r.fail("packet " + std::to_string(k) + " declares size " + std::to_string(valid) +
               " > 1500 data bytes");
      m.packets.push_back({offset_of(data, p), valid, stamp});
    }
  } else if (type == kNebulaPackets) {
    m.stamp = read_header(r);
    const std::uint32_t n = r.sequence_count(8 + 4, "packets");
    m.packets.reserve(n);
    for (std::uint32_t k = 0; k < n; ++k) {
      const double stamp = read_time(r, "packets[].stamp");
      std::size_t len = 0;
      const std::uint8_t* p = r.byte_sequence(len, "packets[].data");
      m.packets.push_back({offset_of(data, p), len, stamp});
    }
  } else {
    r.fail("type " + type + " is not a packet message");
  }
  if (m.stamp == 0.0) m.stamp = log_time;
  return m;
}

}  // namespace dloam::io
