// CDR: alignment relative to the byte after the encapsulation header, both byte orders, bounds
// checks naming the message; the packet messages of every supported driver type.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dloam/io/cdr.hpp"
#include "dloam/io/packet_messages.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using dloam::test::input_error_of;
using ::testing::HasSubstr;

TEST(Cdr, AlignmentIsRelativeToTheByteAfterTheHeader) {
  // u8, then u32 at offset 4, then u64 at offset 8, string, u16: little-endian.
  const std::vector<std::uint8_t> le = {0x00, 0x01, 0x00, 0x00,                          // header
                                        0x07, 0xAA, 0xAA, 0xAA,                          // u8 + padding
                                        0x78, 0x56, 0x34, 0x12,                          // u32
                                        0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80,  // u64
                                        0x03, 0x00, 0x00, 0x00, 'h',  'i',  0x00,        // string "hi"
                                        0xAA, 0x34, 0x12};                               // pad + u16
  io::CdrReader r(le.data(), le.size(), "m");
  EXPECT_FALSE(r.big_endian());
  EXPECT_EQ(r.u8("a"), 7);
  EXPECT_EQ(r.u32("b"), 0x12345678u);
  EXPECT_EQ(r.u64("c"), 0x8000000000000001ull);
  EXPECT_EQ(r.string("d"), "hi");
  EXPECT_EQ(r.u16("e"), 0x1234);
  EXPECT_EQ(r.remaining(), 0u);
  // The same values big-endian.
  const std::vector<std::uint8_t> be = {0x00, 0x00, 0x00, 0x00, 0x07, 0,   0, 0, 0x12, 0x34,
                                        0x56, 0x78, 0x80, 0,    0,    0,   0, 0, 0,    0x01,
                                        0,    0,    0,    3,    'h',  'i', 0, 0, 0x12, 0x34};
  io::CdrReader b(be.data(), be.size(), "m");
  EXPECT_TRUE(b.big_endian());
  EXPECT_EQ(b.u8("a"), 7);
  EXPECT_EQ(b.u32("b"), 0x12345678u);
  EXPECT_EQ(b.u64("c"), 0x8000000000000001ull);
  EXPECT_EQ(b.string("d"), "hi");
  EXPECT_EQ(b.u16("e"), 0x1234);
}

TEST(Cdr, WriterAndReaderAgree) {
  io::CdrWriter w;
  w.u8(1);
  w.f64(2.5);
  w.string("frame");
  w.boolean(true);
  w.u32(77);
  const std::uint8_t raw[3] = {9, 8, 7};
  w.byte_sequence(raw, 3);
  w.i32(-5);
  const auto data = w.data();
  EXPECT_EQ(data[4 + 8], 0);  // f64 at offset 8 after the header (7 padding bytes)
  io::CdrReader r(data.data(), data.size(), "w");
  EXPECT_EQ(r.u8("a"), 1);
  EXPECT_EQ(r.f64("b"), 2.5);
  EXPECT_EQ(r.string("c"), "frame");
  EXPECT_TRUE(r.boolean("d"));
  EXPECT_EQ(r.u32("e"), 77u);
  std::size_t n = 0;
  const std::uint8_t* p = r.byte_sequence(n, "f");
  ASSERT_EQ(n, 3u);
  EXPECT_EQ(p[2], 7);
  EXPECT_EQ(r.i32("g"), -5);
}

TEST(Cdr, ShortMessagesAndBadHeadersAreInputErrorsNamingTheMessage) {
  const std::vector<std::uint8_t> m = {0x00, 0x01, 0x00, 0x00, 0x01, 0x02};
  io::CdrReader r(m.data(), m.size(), "a.db3: topic /p, message 3");
  EXPECT_THAT(input_error_of([&] { r.u32("count"); }),
              HasSubstr("a.db3: topic /p, message 3: message shorter than its fields (count: needs 4 bytes"));
  const std::vector<std::uint8_t> s = {0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0x7F};
  io::CdrReader rs(s.data(), s.size(), "x");
  EXPECT_THAT(input_error_of([&] { rs.string("frame_id"); }),
              HasSubstr("x: message shorter than its fields (frame_id"));
  const std::vector<std::uint8_t> pl = {0x00, 0x03, 0x00, 0x00};
  EXPECT_THAT(input_error_of([&] { io::CdrReader(pl.data(), pl.size(), "y"); }),
              HasSubstr("y: unsupported CDR encapsulation 3"));
  EXPECT_THAT(input_error_of([&] { io::CdrReader(pl.data(), 2, "z"); }),
              HasSubstr("z: message shorter than its fields"));
}

/// A header (stamp, frame_id) as every packet message starts.
void header(io::CdrWriter& w, std::int32_t sec, std::uint32_t nsec, const std::string& frame) {
  w.i32(sec);
  w.u32(nsec);
  w.string(frame);
}

TEST(PacketMessages, EveryDriverTypeDecodesToItsPackets) {
  std::vector<std::uint8_t> payload(1206);
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<std::uint8_t>(i);
  {  // VelodyneScan: fixed 1206-byte arrays, 2 padding bytes between packets
    io::CdrWriter w;
    header(w, 100, 500000000, "velodyne");
    w.u32(2);
    for (int k = 0; k < 2; ++k) {
      w.i32(100 + k);
      w.u32(0);
      w.bytes(payload.data(), 1206);
    }
    const auto d = w.data();
    const auto m = io::decode_packet_message("velodyne_msgs/msg/VelodyneScan", d.data(), d.size(), 0.0, "v");
    ASSERT_EQ(m.packets.size(), 2u);
    EXPECT_DOUBLE_EQ(m.stamp, 100.5);
    EXPECT_DOUBLE_EQ(m.packets[1].stamp, 101.0);
    EXPECT_EQ(m.packets[1].size, 1206u);
    EXPECT_EQ(d[m.packets[1].offset + 7], 7);
    // Cut one byte short: the error names the message.
    EXPECT_THAT(
        input_error_of([&] {
          io::decode_packet_message("velodyne_msgs/msg/VelodyneScan", d.data(), d.size() - 1, 0.0,
                                    "b.db3: topic /velodyne_packets, message 2");
        }),
        HasSubstr(
            "b.db3: topic /velodyne_packets, message 2: message shorter than its fields (packets[].data"));
  }
  {  // PandarScan: 1500-byte arrays with a valid size
    io::CdrWriter w;
    header(w, 5, 0, "hesai");
    w.u32(1);
    w.i32(6);
    w.u32(250000000);
    std::vector<std::uint8_t> block(1500, 0x5A);
    w.bytes(block.data(), block.size());
    w.u32(1080);
    const auto d = w.data();
    const auto m = io::decode_packet_message("pandar_msgs/msg/PandarScan", d.data(), d.size(), 0.0, "h");
    ASSERT_EQ(m.packets.size(), 1u);
    EXPECT_EQ(m.packets[0].size, 1080u);
    EXPECT_DOUBLE_EQ(m.packets[0].stamp, 6.25);
    auto bad = d;
    bad[bad.size() - 2] = 0x10;  // size 4152 > 1500
    EXPECT_THAT(input_error_of([&] {
                  io::decode_packet_message("pandar_msgs/msg/PandarScan", bad.data(), bad.size(), 0.0, "h");
                }),
                HasSubstr("h: packet 0 declares size"));
  }
  {  // NebulaPackets: variable-length packets
    io::CdrWriter w;
    header(w, 7, 0, "lidar");
    w.u32(3);
    for (std::size_t k = 0; k < 3; ++k) {
      w.i32(7);
      w.u32(static_cast<std::uint32_t>(k));
      w.byte_sequence(payload.data(), 100 + k);
    }
    const auto d = w.data();
    const auto m = io::decode_packet_message("nebula_msgs/msg/NebulaPackets", d.data(), d.size(), 0.0, "n");
    ASSERT_EQ(m.packets.size(), 3u);
    EXPECT_EQ(m.packets[2].size, 102u);
    EXPECT_EQ(d[m.packets[2].offset + 101], 101);
    // A count beyond what the message can hold is caught before anything is allocated.
    auto huge = d;
    const std::size_t count_at = 4 + 8 + 4 + 8;  // header, stamp, "lidar\0" padded to 8
    huge[count_at + 3] = 0x7F;
    EXPECT_THAT(input_error_of([&] {
                  io::decode_packet_message("nebula_msgs/msg/NebulaPackets", huge.data(), huge.size(), 0.0,
                                            "n");
                }),
                HasSubstr("n: message shorter than its fields (packets:"));
  }
  for (const char* type : {"ouster_sensor_msgs/msg/PacketMsg", "ouster_msgs/msg/PacketMsg"}) {
    io::CdrWriter plain;  // uint8[] buf alone: stamped with the log time
    plain.byte_sequence(payload.data(), 1206);
    auto d = plain.data();
    auto m = io::decode_packet_message(type, d.data(), d.size(), 42.0, "o");
    ASSERT_EQ(m.packets.size(), 1u);
    EXPECT_EQ(m.packets[0].size, 1206u);
    EXPECT_EQ(m.packets[0].offset, 8u);
    EXPECT_DOUBLE_EQ(m.packets[0].stamp, 42.0);
    io::CdrWriter with_header;  // header + buf
    header(with_header, 9, 0, "os_lidar");
    with_header.byte_sequence(payload.data(), 1000);
    d = with_header.data();
    m = io::decode_packet_message(type, d.data(), d.size(), 42.0, "o");
    ASSERT_EQ(m.packets.size(), 1u);
    EXPECT_EQ(m.packets[0].size, 1000u);
    EXPECT_DOUBLE_EQ(m.packets[0].stamp, 9.0);
    EXPECT_EQ(d[m.packets[0].offset + 999], static_cast<std::uint8_t>(999));
  }
  EXPECT_THAT(input_error_of([&] {
                const std::vector<std::uint8_t> d = {0, 1, 0, 0};
                io::decode_packet_message("sensor_msgs/msg/Imu", d.data(), d.size(), 0.0, "i");
              }),
              HasSubstr("i: type sensor_msgs/msg/Imu is not a packet message"));
}

}  // namespace
}  // namespace dloam
