// The same sensor data in other containers gives the same scans through the vendor decoders: an
// Ouster capture as an ouster-ros style bag (lidar and IMU packet topics, the metadata JSON on a
// topic), a Velodyne capture as an MCAP of VelodyneScan messages, and an Ouster capture re-recorded
// as a pcapng of 1500-byte IPv4 fragments behind a VLAN tag.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "dloam/io/cdr.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/pcap.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "pcap_test_util.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;
namespace fs = std::filesystem;

const std::string kSensors = DLOAM_SENSORS_DIR;

std::vector<io::UdpDatagram> datagrams(const std::string& pcap) {
  io::PcapReader reader(pcap);
  std::vector<io::UdpDatagram> out;
  io::UdpDatagram d;
  while (reader.next(d)) out.push_back(d);
  return out;
}

std::int64_t ns(double t) { return static_cast<std::int64_t>(std::llround(t * 1e9)); }

void expect_same_scans(const io::Sequence& a, const io::Sequence& b, const std::string& label) {
  ASSERT_EQ(a.size(), b.size()) << label;
  ASSERT_TRUE(a.sensor && b.sensor) << label;
  EXPECT_EQ(a.sensor->N_scan, b.sensor->N_scan) << label;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const PointCloud x = a.read_scan(i), y = b.read_scan(i);
    ASSERT_EQ(x.size(), y.size()) << label << " scan " << i;
    ASSERT_GT(x.size(), 1000u) << label;
    for (std::size_t k = 0; k < x.size(); ++k) ASSERT_EQ(x.xyz[k], y.xyz[k]) << label << " scan " << i;
    EXPECT_EQ(x.intensity, y.intensity) << label;
  }
}

TEST(RecordingVendors, OusterBagWithLidarImuAndMetadataTopicsGivesThePcapScans) {
  const std::string pcap = kSensors + "/ouster/OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  const std::string json = kSensors + "/ouster/OS-1-128_v2.3.0_1024x10.json";
  if (!fs::exists(pcap)) GTEST_SKIP() << "no " << pcap;
  TempDir dir;
  const std::string bag = dir.file("ouster_bag");
  {
    io::Rosbag2Writer w(bag);
    w.add_topic("/ouster/lidar_packets", "ouster_sensor_msgs/msg/PacketMsg");
    w.add_topic("/ouster/imu_packets", "ouster_sensor_msgs/msg/PacketMsg");
    w.add_topic("/ouster/metadata", "std_msgs/msg/String");
    std::ifstream in(json);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    io::CdrWriter meta;
    meta.string(text);
    const auto datas = datagrams(pcap);
    w.write("/ouster/metadata", ns(datas.front().time), meta.data().data(), meta.data().size());
    for (const auto& d : datas) {
      io::CdrWriter m;  // uint8[] buf alone (the older layout): stamped with the bag's time
      m.byte_sequence(d.payload.data(), d.payload.size());
      w.write(d.dst_port == 7502 ? "/ouster/lidar_packets" : "/ouster/imu_packets", ns(d.time),
              m.data().data(), m.data().size());
    }
    w.close();
  }
  io::InputOptions with_json;
  with_json.metadata = json;
  const io::Sequence from_pcap = io::open_sequence(pcap, with_json);
  const io::Sequence from_bag = io::open_sequence(bag);  // topic and metadata found in the bag
  EXPECT_EQ(from_pcap.size(), 3u);
  expect_same_scans(from_pcap, from_bag, "ouster bag");
  EXPECT_THAT(from_bag.source->describe(), HasSubstr("topic /ouster/lidar_packets"));
  EXPECT_THAT(from_bag.source->describe(), HasSubstr("metadata from the bag's metadata topic"));
  for (std::size_t i = 0; i < from_bag.size(); ++i) EXPECT_NEAR(from_bag.times[i], from_pcap.times[i], 1e-6);
}

TEST(RecordingVendors, VelodyneCaptureAsAnMcapOfVelodyneScansGivesThePcapScans) {
  const std::string pcap = kSensors + "/velodyne/rust-lidar-utils/hdl32_example.pcap";
  if (!fs::exists(pcap)) GTEST_SKIP() << "no " << pcap;
  TempDir dir;
  const std::string mcap = dir.file("hdl32.mcap");
  {
    io::McapWriterOptions o;
    o.compression = "lz4";
    io::McapWriter w(mcap, o);
    const auto channel = w.add_channel("/velodyne_packets", "cdr",
                                       w.add_schema("velodyne_msgs/msg/VelodyneScan", "ros2msg", ""));
    std::vector<io::UdpDatagram> data;
    for (auto& d : datagrams(pcap))
      if (d.dst_port == 2368) data.push_back(std::move(d));
    for (std::size_t first = 0; first < data.size(); first += 100) {  // about 2/3 of a rotation each
      const std::size_t n = std::min<std::size_t>(100, data.size() - first);
      io::CdrWriter m;
      const double t = data[first].time;
      m.i32(static_cast<std::int32_t>(std::floor(t)));
      m.u32(static_cast<std::uint32_t>(std::llround((t - std::floor(t)) * 1e9)));
      m.string("velodyne");
      m.u32(static_cast<std::uint32_t>(n));
      for (std::size_t k = first; k < first + n; ++k) {
        const double s = std::floor(data[k].time);
        m.i32(static_cast<std::int32_t>(s));
        m.u32(static_cast<std::uint32_t>(std::llround((data[k].time - s) * 1e9)));
        m.bytes(data[k].payload.data(), 1206);
      }
      w.write(channel, static_cast<std::uint64_t>(ns(data[first + n - 1].time)), m.data().data(),
              m.data().size());
    }
    w.close();
  }
  const io::Sequence from_pcap = io::open_sequence(pcap);
  const io::Sequence from_mcap = io::open_sequence(mcap);
  EXPECT_EQ(from_pcap.size(), 5u);  // 5 full rotations
  expect_same_scans(from_pcap, from_mcap, "velodyne mcap");
}

TEST(RecordingVendors, FragmentedVlanTaggedPcapngGivesTheSameScans) {
  const std::string pcap = kSensors + "/ouster/OS-2-128-U1_v2.3.0_1024x10.pcap";
  if (!fs::exists(pcap)) GTEST_SKIP() << "no " << pcap;
  TempDir dir;
  std::vector<Record> records;
  std::uint16_t id = 0;
  for (const auto& d : datagrams(pcap)) {
    // 24832-byte lidar packets as a tcpdump on a 1500-byte MTU link records them.
    const Bytes u = udp(d.src_port, d.dst_port, Bytes(d.payload.begin(), d.payload.end()));
    for (const auto& f : fragments(u, 1480, ++id)) records.push_back({d.time, ethernet(f, 1)});
  }
  const std::string ng = dir.file("OS-2-128-U1_v2.3.0_1024x10-fragmented.pcapng");
  const Bytes b = pcapng_file(records);
  std::ofstream(ng, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
  fs::copy_file(kSensors + "/ouster/OS-2-128-U1_v2.3.0_1024x10.json",
                dir.file("OS-2-128-U1_v2.3.0_1024x10.json"));
  const io::Sequence original = io::open_sequence(pcap);  // its JSON beside it
  const io::Sequence fragmented = io::open_sequence(ng);  // the JSON named like its stem's start
  expect_same_scans(original, fragmented, "fragmented pcapng");
  EXPECT_THAT(fragmented.source->describe(), HasSubstr("reassembled from"));
}

}  // namespace
}  // namespace dloam
