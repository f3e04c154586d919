// pcap / pcapng captures: the sensor recordings' datagram counts and sizes per port (as the
// sensors README states them), link types, VLAN tags, IPv4 reassembly, damaged files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "dloam/io/pcap.hpp"
#include "pcap_test_util.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;

const std::string kSensors = DLOAM_SENSORS_DIR;

/// (port, payload size) -> datagrams, over the whole capture.
std::map<std::pair<int, std::size_t>, std::size_t> census(io::PcapReader& reader) {
  std::map<std::pair<int, std::size_t>, std::size_t> counts;
  io::UdpDatagram d;
  std::size_t expected_index = 0;
  while (reader.next(d)) {
    EXPECT_EQ(d.index, expected_index++);
    ++counts[{d.dst_port, d.payload.size()}];
  }
  return counts;
}

void write_bytes(const std::string& path, const Bytes& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
}

using Census = std::map<std::pair<int, std::size_t>, std::size_t>;

TEST(Pcap, SensorRecordingsHoldTheDatagramsTheReadmeLists) {
  if (!std::filesystem::exists(kSensors + "/README.md")) GTEST_SKIP() << "no " << kSensors;
  const std::vector<std::pair<std::string, Census>> cases = {
      {"velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap", {{{2368, 1206}, 1902}, {{8308, 512}, 367}}},
      {"velodyne/rust-lidar-utils/hdl32_example.pcap", {{{2368, 1206}, 876}, {{8308, 512}, 100}}},
      {"velodyne/rust-lidar-utils/velodyne_example.pcap", {{{2368, 1206}, 84}}},
      {"velodyne/rust-lidar-utils/velodyne_vlp16.pcap", {{{2368, 1206}, 84}, {{8308, 512}, 16}}},
      {"velodyne/rust-lidar-utils/velodyne_vlp32.pcap", {{{2368, 1206}, 91}, {{8308, 512}, 9}}},
      {"ouster/OS-0-128-U1_v2.3.0_1024x10.pcap", {{{7502, 8448}, 64}, {{7503, 48}, 10}}},
      {"ouster/OS-0-32-U1_v2.2.0_1024x10.pcap", {{{7502, 8448}, 64}, {{7503, 48}, 10}}},
      {"ouster/OS-0-32-U1_v2.2.0_1024x10-single-packet.pcap", {{{7502, 8448}, 1}}},
      {"ouster/OS-1-128_v2.3.0_1024x10_lb_n3.pcap", {{{7502, 8448}, 192}, {{7503, 48}, 30}}},
      {"ouster/OS-1-128_767798045_1024x10_20230712_120049.pcap", {{{7502, 16640}, 8}, {{7503, 48}, 2}}},
      {"ouster/OS-1-64_1024x10_fw20.pcap", {{{7502, 12608}, 64}, {{7503, 48}, 11}}},
      {"ouster/OS-1-32-G_v2.1.1_1024x10.pcap", {{{7502, 6464}, 64}}},
      {"ouster/OS-2-128-U1_v2.3.0_1024x10.pcap", {{{7502, 24832}, 64}, {{7503, 48}, 10}}},
      {"ouster/OS-2-32-U0_v2.0.0_1024x10.pcap", {{{7502, 6464}, 64}}},
      {"ouster/bad/crc_test.pcap", {{{7502, 8448}, 34}, {{7503, 48}, 10}}},
      {"ouster/bad/empty_pcap.pcap", {}},
  };
  for (const auto& [file, expected] : cases) {
    io::PcapReader reader(kSensors + "/" + file);
    EXPECT_EQ(census(reader), expected) << file;
    EXPECT_EQ(reader.stats().malformed + reader.stats().truncated + reader.stats().incomplete, 0u) << file;
    EXPECT_EQ(reader.link_type(), 1) << file;  // Ethernet
  }
}

TEST(Pcap, PortSelectionTimesAndRecordIndices) {
  const std::string file = kSensors + "/velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
  io::PcapOptions options;
  options.port = 2368;
  io::PcapReader reader(file, options);
  io::UdpDatagram d;
  std::size_t n = 0;
  double last = 0.0, first = 0.0;
  std::size_t last_record = 0;
  while (reader.next(d)) {
    EXPECT_EQ(d.dst_port, 2368);
    EXPECT_EQ(d.payload.size(), 1206u);
    EXPECT_EQ(d.payload[0], 0xFF);  // first block flag FF EE
    EXPECT_EQ(d.payload[1], 0xEE);
    if (n == 0) first = d.time;
    EXPECT_GE(d.time, last);
    if (n > 0) {
      EXPECT_GT(d.record, last_record);
    }
    last = d.time;
    last_record = d.record;
    ++n;
  }
  EXPECT_EQ(n, 1902u);
  EXPECT_EQ(reader.stats().records, 2269u);
  EXPECT_EQ(reader.stats().other_port, 367u);
  EXPECT_NEAR(last - first, 2.524, 0.01);  // the README's duration (first to last record)
  EXPECT_GT(first, 1.41e9);                // 2014-11-04
  EXPECT_LT(first, 1.416e9);
}

TEST(Pcap, PositionPacketsKeepTheirUdpLengthDespiteAWrongIpTotalLength) {
  // The VLP-16 captures of 2014 carry IPv4 total length 1234 in 554-byte frames.
  const std::string file = kSensors + "/velodyne/rust-lidar-utils/velodyne_vlp16.pcap";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
  io::PcapOptions options;
  options.port = 8308;
  io::PcapReader reader(file, options);
  io::UdpDatagram d;
  std::size_t n = 0;
  while (reader.next(d)) {
    EXPECT_EQ(d.payload.size(), 512u);
    ++n;
  }
  EXPECT_EQ(n, 16u);
  // The same lie in a synthetic frame: total length 1234, 540 IP bytes present.
  const Bytes ip = ipv4(udp(10110, 8308, payload(512, 3)), 7, 0, false, 17, 1234);
  auto synthetic = io::PcapReader::from_memory(pcap_file(1, {{1.0, ethernet(ip)}}), "lie.pcap");
  ASSERT_TRUE(synthetic->next(d));
  EXPECT_EQ(d.payload, payload(512, 3));
}

TEST(Pcap, LinkTypesVlanTagsAndTimestampPrecision) {
  const Bytes data = payload(1206, 5);
  const Bytes ip = ipv4(udp(2368, 2368, data));
  struct Case {
    const char* name;
    int linktype;
    Bytes frame;
    bool ns;
  };
  const std::vector<Case> cases = {
      {"ethernet", 1, ethernet(ip), false},
      {"vlan", 1, ethernet(ip, 1), true},
      {"qinq", 1, ethernet(ip, 2), false},
      {"sll", 113, linux_cooked(ip), true},
      {"raw", 101, ip, false},
      {"ipv4", 228, ip, true},
  };
  for (const auto& c : cases) {
    const double t = 1500000000.123456;
    auto reader = io::PcapReader::from_memory(
        pcap_file(c.linktype, {{t, c.frame}, {t + 1, ethernet(ip, 0, 0x0806)}}, c.ns), c.name);
    io::UdpDatagram d;
    ASSERT_TRUE(reader->next(d)) << c.name;
    EXPECT_EQ(d.payload, data) << c.name;
    EXPECT_EQ(d.dst_port, 2368) << c.name;
    EXPECT_EQ(d.src_ip, 0xC0A801C9u) << c.name;
    EXPECT_NEAR(d.time, t, 1e-6) << c.name;
    EXPECT_FALSE(reader->next(d)) << c.name;
    EXPECT_EQ(reader->stats().records, 2u) << c.name;
  }
  // pcapng through libpcap: nanosecond timestamps.
  const double t = 1600000000.000000123;
  auto ng =
      io::PcapReader::from_memory(pcapng_file({{t, ethernet(ip, 1)}, {t + 0.5, ethernet(ip)}}), "x.pcapng");
  io::UdpDatagram d;
  ASSERT_TRUE(ng->next(d));
  EXPECT_EQ(d.payload, data);
  EXPECT_NEAR(d.time, t, 1e-6);
  ASSERT_TRUE(ng->next(d));
  EXPECT_NEAR(d.time, t + 0.5, 1e-6);
  EXPECT_FALSE(ng->next(d));
}

TEST(Pcap, FragmentsAreReassembledInAnyOrderAndLostOnesAreCounted) {
  // An Ouster-size datagram (24832 B) in 1480-byte fragments, sent backwards and interleaved with
  // a second datagram; a third datagram loses a fragment.
  const Bytes big = payload(24832, 1), other = payload(8448, 2), lost = payload(6464, 3);
  std::vector<Bytes> a = fragments(udp(7502, 7502, big), 1480, 10);
  std::vector<Bytes> b = fragments(udp(7502, 7502, other), 1480, 11);
  std::vector<Bytes> c = fragments(udp(7502, 7502, lost), 1480, 12);
  std::vector<Record> records;
  double t = 100.0;
  for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
    if (i < a.size()) records.push_back({t += 1e-5, ethernet(a[a.size() - 1 - i])});
    if (i < b.size()) records.push_back({t += 1e-5, ethernet(b[i])});
  }
  c.erase(c.begin() + 2);
  for (const auto& f : c) records.push_back({t += 1e-5, ethernet(f)});
  records.push_back({t += 1e-5, ethernet(ipv4(udp(7502, 7503, payload(48, 9))))});
  auto reader = io::PcapReader::from_memory(pcap_file(1, records), "frag.pcap");
  io::UdpDatagram d;
  std::vector<Bytes> got;
  while (reader->next(d)) got.push_back(d.payload);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0], other);  // completes first (its last fragment comes before big's first)
  EXPECT_EQ(got[1], big);
  EXPECT_EQ(got[2], payload(48, 9));
  EXPECT_EQ(reader->stats().reassembled, 2u);
  EXPECT_EQ(reader->stats().incomplete, 1u);
  EXPECT_THAT(reader->stats().describe(), HasSubstr("1 fragmented datagrams incomplete"));
}

TEST(Pcap, PendingFragmentsAreBoundedAndTimeOut) {
  io::PcapOptions options;
  options.max_pending_fragments = 4;
  std::vector<Record> records;
  double t = 10.0;
  for (std::uint16_t id = 0; id < 10; ++id)  // 10 first fragments that never complete
    records.push_back({t += 0.01, ethernet(fragments(udp(1, 2, payload(4000, id)), 1480, id)[0])});
  const Bytes late = payload(3000, 42);
  const auto parts = fragments(udp(1, 2, late), 1480, 99);
  records.push_back({t, ethernet(parts[0])});
  records.push_back({t + 5.0, ethernet(parts[1])});  // after the 2 s timeout
  records.push_back({t + 5.0, ethernet(parts[2])});
  auto reader = io::PcapReader::from_memory(pcap_file(1, records), "many.pcap", options);
  io::UdpDatagram d;
  EXPECT_FALSE(reader->next(d));
  // 6 evicted beyond 4 pending, 4 + the late one's first part timed out, the late tail incomplete at the end.
  EXPECT_EQ(reader->stats().incomplete, 12u);
}

TEST(Pcap, TruncatedAndForeignFilesAreInputErrorsNamingFileAndRecord) {
  const std::string file = kSensors + "/velodyne/rust-lidar-utils/velodyne_example.pcap";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
  TempDir dir;
  std::ifstream in(file, std::ios::binary);
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Cut in the middle of record 40 (24-byte file header, records of 16 + 1248 bytes).
  bytes.resize(24 + 40 * (16 + 1248) + 16 + 600);
  const std::string cut = dir.file("cut.pcap");
  write_bytes(cut, bytes);
  io::PcapReader reader(cut);
  io::UdpDatagram d;
  std::size_t n = 0;
  const std::string error = input_error_of([&] {
    while (reader.next(d)) ++n;
  });
  EXPECT_EQ(n, 40u);
  EXPECT_THAT(error, HasSubstr(cut + ": record 40: "));
  EXPECT_THAT(error, HasSubstr("truncated"));

  const std::string text = dir.file("notes.pcap");
  write_text(text, "this is not a capture, just a text file with a .pcap name\n");
  EXPECT_THAT(input_error_of([&] { io::PcapReader r(text); }),
              HasSubstr(text + ": not a readable pcap or pcapng capture"));
  const std::string empty = dir.file("empty.pcap");
  write_text(empty, "");
  EXPECT_THAT(input_error_of([&] { io::PcapReader r(empty); }), HasSubstr(empty + ": empty file"));
  EXPECT_THAT(input_error_of([&] { io::PcapReader r(dir.file("missing.pcap")); }), HasSubstr("not found"));
  EXPECT_THAT(input_error_of([&] { io::PcapReader::from_memory(pcap_file(105, {}), "wifi.pcap"); }),
              HasSubstr("wifi.pcap: link type IEEE802_11 (105) is not supported"));
}

TEST(Pcap, MalformedAndSnapshotCutFramesAreCountedNotReturned) {
  const Bytes ok = ethernet(ipv4(udp(1, 2368, payload(100, 1))));
  Bytes cut = ethernet(ipv4(udp(1, 2368, payload(1206, 1))));
  cut.resize(300);  // snaplen 300
  Bytes bad_ihl = ok;
  bad_ihl[14] = 0x43;  // IHL 12 bytes
  const Bytes tiny(10, 0);
  auto reader = io::PcapReader::from_memory(
      pcap_file(1, {{1, ok}, Record{2, cut, 1248}, {3, bad_ihl}, {4, tiny}, {5, ok}}), "odd.pcap");
  io::UdpDatagram d;
  std::size_t n = 0;
  while (reader->next(d)) ++n;
  EXPECT_EQ(n, 2u);
  EXPECT_EQ(reader->stats().truncated, 1u);
  EXPECT_EQ(reader->stats().malformed, 2u);
  EXPECT_THAT(reader->stats().describe(), HasSubstr("first: record 1: UDP length 1214 but only"));
}

TEST(Pcap, SeekReturnsToARecordedPosition) {
  std::vector<Record> records;
  for (int i = 0; i < 20; ++i) records.push_back({1.0 + i, ethernet(ipv4(udp(1, 2368, payload(64, i))))});
  auto reader = io::PcapReader::from_memory(pcap_file(1, records), "seek.pcap");
  io::UdpDatagram d;
  for (int i = 0; i < 7; ++i) ASSERT_TRUE(reader->next(d));
  const auto pos = reader->position();
  ASSERT_TRUE(pos.has_value());
  ASSERT_TRUE(reader->next(d));
  const Bytes eighth = d.payload;
  while (reader->next(d)) {
  }
  reader->seek(*pos);
  ASSERT_TRUE(reader->next(d));
  EXPECT_EQ(d.payload, eighth);
  EXPECT_EQ(d.index, 7u);
  EXPECT_EQ(d.record, 7u);
}

}  // namespace
}  // namespace dloam
