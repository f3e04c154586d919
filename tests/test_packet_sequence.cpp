// Raw-packet recordings as sequences, with a stand-in scanner (a rotating "sensor" whose packets
// carry an azimuth): the indexing pass, scans read by index in any order equal to one sequential
// decode, scan times, the per-point sweep fraction, captures and bags alike; bad recordings.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "dloam/core/sensor.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/cdr.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/packet_sequence.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "pcap_test_util.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;

constexpr std::size_t kPacketSize = 64;
constexpr std::size_t kPointsPerPacket = 8;

/// A stand-in sensor: packets 'F' 'K', uint16 azimuth (0.01 deg), then ranges. A rotation ends one
/// packet after the azimuth wraps (the wrap packet still belongs to the old one), so a scan
/// depends on the packets before it, as real decoders' scans do.
class FakeScanner : public drivers::Scanner {
 public:
  static inline std::size_t fed = 0;  ///< packets added to any FakeScanner
  void add(const drivers::Packet& p, std::vector<drivers::Scan>& done) override {
    ++fed;
    if (p.size != kPacketSize || p.data[0] != 'F' || p.data[1] != 'K')
      throw InputError(p.where + ": not a fake packet");
    std::uint16_t az = 0;
    std::memcpy(&az, p.data + 2, 2);
    if (wrapped_) {  // the packet after the wrap closes the rotation
      current_.complete = seen_start_;
      done.push_back(std::move(current_));
      current_ = drivers::Scan{};
      wrapped_ = false;
      seen_start_ = true;
    }
    if (have_last_ && az < last_az_) wrapped_ = true;
    if (!have_last_) seen_start_ = az == 0;
    have_last_ = true;
    last_az_ = az;
    const double a = az * 0.01 * M_PI / 180.0;
    for (std::size_t k = 0; k < kPointsPerPacket; ++k) {
      const double r = 5.0 + p.data[4 + k] * 0.1;
      if (current_.xyz.empty()) current_.start = p.stamp;
      current_.xyz.emplace_back(r * std::cos(a), r * std::sin(a), 0.1 * static_cast<double>(k));
      current_.intensity.push_back(static_cast<float>(p.data[4 + k]));
      current_.ring.push_back(static_cast<std::uint16_t>(k));
      current_.return_id.push_back(0);
      current_.stamps.push_back(p.stamp + 1e-5 * static_cast<double>(k));
      current_.end = current_.stamps.back();
    }
  }
  void finish(std::vector<drivers::Scan>& done) override {
    if (current_.xyz.empty()) return;
    current_.complete = false;
    done.push_back(std::move(current_));
    current_ = drivers::Scan{};
  }
  [[nodiscard]] SensorConfig sensor() const override {
    SensorConfig s = sensor_preset("VLP-16");
    s.preset = "fake";
    return s;
  }
  [[nodiscard]] std::string describe() const override { return "fake sensor"; }

 private:
  drivers::Scan current_;
  std::uint16_t last_az_ = 0;
  bool have_last_ = false, wrapped_ = false, seen_start_ = false;
};

io::ScannerFactory fake_factory() {
  return [](const std::vector<drivers::Packet>&) { return std::make_unique<FakeScanner>(); };
}

/// Packets of `rotations` turns at 10 Hz, 36 packets each (10 deg apart), starting at 180 deg
/// and ending at 170 deg: a partial rotation at each end.
struct FakeRecording {
  std::vector<Bytes> payloads;
  std::vector<double> times;
};
FakeRecording fake_packets(int rotations) {
  FakeRecording r;
  std::mt19937 rng(7);
  const int total = 36 * rotations;
  for (int i = 0; i < total; ++i) {
    const int step = (i + 18) % 36;
    Bytes b(kPacketSize, 0);
    b[0] = 'F';
    b[1] = 'K';
    const auto az = static_cast<std::uint16_t>(step * 1000);
    std::memcpy(b.data() + 2, &az, 2);
    for (std::size_t k = 4; k < kPacketSize; ++k) b[k] = static_cast<std::uint8_t>(rng() % 200);
    r.payloads.push_back(b);
    r.times.push_back(1600000000.0 + i * (0.1 / 36));
  }
  return r;
}

std::string write_fake_pcap(const TempDir& dir, const FakeRecording& f) {
  std::vector<Record> records;
  for (std::size_t i = 0; i < f.payloads.size(); ++i) {
    records.push_back({f.times[i], ethernet(ipv4(udp(2368, 2368, f.payloads[i])))});
    if (i % 10 == 0) records.push_back({f.times[i], ethernet(ipv4(udp(8308, 8308, payload(512, 1))))});
  }
  const std::string path = dir.file("fake.pcap");
  const Bytes b = pcap_file(1, records, true);  // ns timestamps
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
  return path;
}

/// The packet times as a recording stores them: whole nanoseconds.
FakeRecording rounded_to_ns(FakeRecording f) {
  for (auto& t : f.times) {
    const double sec = std::floor(t);
    t = sec + 1e-9 * static_cast<double>(std::llround((t - sec) * 1e9));
  }
  return f;
}

/// Every scan of one sequential decode, for comparison.
std::vector<drivers::Scan> decode_all(const FakeRecording& f) {
  FakeScanner s;
  std::vector<drivers::Scan> done;
  for (std::size_t i = 0; i < f.payloads.size(); ++i) {
    drivers::Packet p;
    p.data = f.payloads[i].data();
    p.size = f.payloads[i].size();
    p.stamp = f.times[i];
    s.add(p, done);
  }
  s.finish(done);
  return done;
}

void expect_scans(const io::Sequence& seq, const std::vector<drivers::Scan>& all, const std::string& label) {
  std::vector<const drivers::Scan*> complete;
  for (const auto& s : all)
    if (s.complete) complete.push_back(&s);
  ASSERT_EQ(complete.size(), 4u) << label;  // the partial head and tail are left out
  ASSERT_EQ(seq.size(), 4u) << label;
  ASSERT_TRUE(seq.sensor.has_value()) << label;
  EXPECT_EQ(seq.sensor->preset, "fake") << label;
  ASSERT_EQ(seq.times.size(), 4u) << label;
  for (const std::size_t i : {2u, 0u, 3u, 1u, 1u, 2u, 3u}) {  // any order, repeats
    const PointCloud c = seq.read_scan(i);
    const drivers::Scan& want = *complete[i];
    EXPECT_EQ(seq.times[i], want.start) << label;
    ASSERT_EQ(c.size(), want.size()) << label << " scan " << i;
    ASSERT_TRUE(c.has_time() && c.has_intensity()) << label;
    for (std::size_t k = 0; k < c.size(); ++k) {
      ASSERT_EQ(c.xyz[k], want.xyz[k]) << label << " scan " << i << " point " << k;
      EXPECT_EQ(c.intensity[k], want.intensity[k]);
      const float f = static_cast<float>((want.stamps[k] - want.start) * 10.0);
      EXPECT_FLOAT_EQ(c.time[k], std::min(f, std::nextafter(1.0f, 0.0f)));
    }
  }
  EXPECT_THAT(seq.source->describe(), HasSubstr("fake sensor"));
  EXPECT_THAT(seq.source->describe(), HasSubstr("4 scans (2 incomplete rotations left out)"));
}

TEST(PacketSequence, ScansReadByIndexEqualOneSequentialDecode) {
  TempDir dir;
  const FakeRecording f = fake_packets(5);
  const auto all = decode_all(rounded_to_ns(f));
  ASSERT_EQ(all.size(), 6u);
  const std::string pcap = write_fake_pcap(dir, f);
  const io::Sequence seq = io::open_packet_sequence(io::pcap_recording(pcap, 2368), fake_factory());
  expect_scans(seq, all, "pcap");
  EXPECT_THAT(seq.source->describe(), HasSubstr("to other ports"));
  for (std::size_t i = 0; i < seq.size(); ++i) EXPECT_THAT(seq.scan_files[i], HasSubstr(pcap + ": scan "));
}

/// A scan is decoded from a resume point two rotations before it, and reading the next scan
/// continues the same decoding: neither starts again from the first packet.
TEST(PacketSequence, ScansAreDecodedFromNearbyResumePoints) {
  TempDir dir;
  const FakeRecording f = fake_packets(8);  // 288 packets
  const std::string pcap = write_fake_pcap(dir, f);
  const io::Sequence seq = io::open_packet_sequence(io::pcap_recording(pcap, 2368), fake_factory());
  ASSERT_EQ(seq.size(), 7u);
  FakeScanner::fed = 0;
  (void)seq.read_scan(6);  // the last complete rotation: packets 234..270
  EXPECT_LE(FakeScanner::fed, 3 * 36u);
  FakeScanner::fed = 0;
  (void)seq.read_scan(2);
  (void)seq.read_scan(3);
  (void)seq.read_scan(4);
  EXPECT_LE(FakeScanner::fed, 3 * 36u + 2 * 36u + 2);
}

/// The same packets as NebulaPackets messages (about half a rotation each) of an MCAP bag and a db3 bag.
TEST(PacketSequence, BagPacketTopicsGiveTheSameScans) {
  TempDir dir;
  const FakeRecording f = fake_packets(5);
  const auto all = decode_all(rounded_to_ns(f));
  std::vector<Bytes> messages;
  std::vector<std::int64_t> stamps;
  for (std::size_t first = 0; first < f.payloads.size(); first += 17) {
    io::CdrWriter w;
    w.i32(static_cast<std::int32_t>(f.times[first]));
    w.u32(0);
    w.string("lidar");
    const std::size_t n = std::min<std::size_t>(17, f.payloads.size() - first);
    w.u32(static_cast<std::uint32_t>(n));
    for (std::size_t k = first; k < first + n; ++k) {
      const double sec = std::floor(f.times[k]);
      w.i32(static_cast<std::int32_t>(sec));
      w.u32(static_cast<std::uint32_t>(std::llround((f.times[k] - sec) * 1e9)));
      w.byte_sequence(f.payloads[k].data(), f.payloads[k].size());
    }
    messages.push_back(w.take());
    stamps.push_back(static_cast<std::int64_t>(f.times[first + n - 1] * 1e9));
  }
  const std::string mcap = dir.file("fake.mcap");
  {
    io::McapWriter w(mcap);
    const auto c =
        w.add_channel("/packets", "cdr", w.add_schema("nebula_msgs/msg/NebulaPackets", "ros2msg", ""));
    for (std::size_t k = 0; k < messages.size(); ++k)
      w.write(c, static_cast<std::uint64_t>(stamps[k]), messages[k].data(), messages[k].size());
    w.close();
  }
  const std::string db3 = dir.file("fake_bag");
  {
    io::Rosbag2Writer w(db3);
    w.add_topic("/packets", "nebula_msgs/msg/NebulaPackets");
    for (std::size_t k = 0; k < messages.size(); ++k)
      w.write("/packets", stamps[k], messages[k].data(), messages[k].size());
    w.close();
  }
  for (const std::string& path : {mcap, db3}) {
    auto bag = std::make_shared<const io::Bag>(path);
    const io::Sequence seq = io::open_packet_sequence(
        io::bag_packet_recording(bag, "/packets", "nebula_msgs/msg/NebulaPackets"), fake_factory());
    expect_scans(seq, all, path);
  }
}

TEST(PacketSequence, RecordingsWithoutUsablePacketsAreInputErrors) {
  TempDir dir;
  const std::string empty = dir.file("empty.pcap");
  {
    const Bytes b = pcap_file(1, {});
    std::ofstream(empty, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
  }
  EXPECT_THAT(input_error_of([&] { io::open_packet_sequence(io::pcap_recording(empty, 0), fake_factory()); }),
              HasSubstr(empty + ": holds no packets"));
  EXPECT_THAT(input_error_of([&] { io::open_sequence(empty); }),
              HasSubstr(empty + ": holds no UDP datagrams"));
  // Datagrams no decoder claims, on the wrong port, or not there at all.
  const FakeRecording f = fake_packets(2);
  const std::string pcap = write_fake_pcap(dir, f);
  EXPECT_THAT(input_error_of([&] { io::open_sequence(pcap); }),
              HasSubstr("is a data packet of a known LiDAR (first: " + pcap +
                        ": packet 0 (record 0), 64 bytes to port 2368"));
  io::InputOptions other;
  other.port = 9999;
  EXPECT_THAT(input_error_of([&] { io::open_sequence(pcap, other); }),
              HasSubstr(pcap + ": no UDP datagrams to port 9999 (2368: 72 datagrams, 8308: 8 datagrams)"));
  // The scanner refuses a packet in the middle: the error names it.
  std::vector<Record> records;
  for (std::size_t i = 0; i < f.payloads.size(); ++i) {
    Bytes p = f.payloads[i];
    if (i == 40) p[0] = 'X';
    records.push_back({f.times[i], ethernet(ipv4(udp(2368, 2368, p)))});
  }
  const std::string bad = dir.file("bad.pcap");
  const Bytes b = pcap_file(1, records);
  std::ofstream(bad, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
  EXPECT_THAT(
      input_error_of([&] { io::open_packet_sequence(io::pcap_recording(bad, 2368), fake_factory()); }),
      HasSubstr(bad + ": packet 40 (record 40): not a fake packet"));
}

TEST(PacketSequence, BagsWithoutCloudOrPacketTopicsAreInputErrors) {
  TempDir dir;
  const std::string path = dir.file("strings");
  {
    io::Rosbag2Writer w(path);
    w.add_topic("/chatter", "std_msgs/msg/String");
    io::CdrWriter m;
    m.string("hello");
    w.write("/chatter", 5, m.data().data(), m.data().size());
    w.add_topic("/a", "sensor_msgs/msg/PointCloud2");
    w.add_topic("/b", "sensor_msgs/msg/PointCloud2");
    w.close();
  }
  EXPECT_THAT(input_error_of([&] { io::open_sequence(path); }),
              HasSubstr(path + ": has several PointCloud2 topics (/a, /b): choose one with --topic"));
  EXPECT_THAT(
      input_error_of([&] { io::open_sequence(path, "/chatter"); }),
      HasSubstr("topic '/chatter' has type std_msgs/msg/String, expected sensor_msgs/msg/PointCloud2 or a "
                "packet message"));
  EXPECT_THAT(input_error_of([&] { io::open_sequence(path, "/a"); }), HasSubstr("topic /a has no messages"));
  const std::string only = dir.file("only_strings");
  {
    io::Rosbag2Writer w(only);
    w.add_topic("/chatter", "std_msgs/msg/String");
    w.close();
  }
  EXPECT_THAT(input_error_of([&] { io::open_sequence(only); }),
              HasSubstr(only + ": no sensor_msgs/msg/PointCloud2 or raw-packet topic (topics: /chatter "
                               "(std_msgs/msg/String))"));
  // A corrupt SQLite file named .db3.
  const std::string junk = dir.file("junk.db3");
  write_text(junk, std::string(3000, '\x17'));
  EXPECT_THAT(input_error_of([&] { io::open_sequence(junk); }),
              HasSubstr(junk + ": not a readable rosbag2 SQLite file"));
  // A text file named .pcap.
  const std::string text = dir.file("text.pcap");
  write_text(text, "not a capture\n");
  EXPECT_THAT(input_error_of([&] { io::open_sequence(text); }),
              HasSubstr(text + ": not a readable pcap or pcapng capture"));
}

TEST(PacketSequence, PerPointTimesAreSweepFractionsOfTheScanRate) {
  drivers::Scan s;
  s.start = 100.0;
  for (const double t : {100.0, 100.025, 100.05, 100.0999, 100.2, 99.9}) {
    s.xyz.emplace_back(1, 0, 0);
    s.stamps.push_back(t);
  }
  const PointCloud c = io::to_point_cloud(s, 10.0);
  ASSERT_TRUE(c.has_time());
  EXPECT_FLOAT_EQ(c.time[0], 0.0f);
  EXPECT_NEAR(c.time[1], 0.25, 1e-6);
  EXPECT_NEAR(c.time[2], 0.5, 1e-6);
  EXPECT_NEAR(c.time[3], 0.999, 1e-5);
  EXPECT_LT(c.time[4], 1.0f);  // clamped
  EXPECT_GT(c.time[4], 0.9999f);
  EXPECT_EQ(c.time[5], 0.0f);
  EXPECT_FALSE(c.has_intensity());
}

}  // namespace
}  // namespace dloam
