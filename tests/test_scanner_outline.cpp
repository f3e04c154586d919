// Scanner::outline_only and Scanner::restart on the real recordings of every vendor: the outlines
// (what a recording's index is made of) are those of the scans decoded with points, and a
// restarted scanner decodes the same scans as the one it came from.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "dloam/drivers/registry.hpp"
#include "dloam/drivers/velodyne.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/packet_sequence.hpp"

namespace dloam {
namespace {

namespace fs = std::filesystem;
const std::string kSensors = DLOAM_SENSORS_DIR;

struct Case {
  std::string path;      ///< under the sensors folder: a capture, or a nebula model folder
  std::string metadata;  ///< Ouster JSON, under the sensors folder
};

/// The bag folder inside a nebula model folder; a capture as it is.
std::string resolve(const std::string& rel) {
  const std::string path = kSensors + "/" + rel;
  if (!fs::is_directory(path)) return path;
  for (const auto& e : fs::directory_iterator(path))
    if (e.is_directory()) return e.path().string();
  return path;
}

std::shared_ptr<io::PacketRecording> recording_of(const std::string& path) {
  if (fs::is_directory(path)) {
    auto bag = std::make_shared<const io::Bag>(path);
    const auto& t = bag->topics().at(0);
    return io::bag_packet_recording(bag, t.name, t.type);
  }
  return io::pcap_recording(path, 0);
}

std::vector<drivers::Scan> decode(drivers::Scanner& scanner, const io::PacketRecording& recording) {
  std::vector<drivers::Scan> done;
  auto stream = recording.open();
  drivers::Packet p;
  while (stream->next(p)) scanner.add(p, done);
  scanner.finish(done);
  return done;
}

void expect_same_points(const drivers::Scan& a, const drivers::Scan& b, const std::string& label) {
  ASSERT_EQ(a.size(), b.size()) << label;
  EXPECT_EQ(a.xyz, b.xyz) << label;
  EXPECT_EQ(a.intensity, b.intensity) << label;
  EXPECT_EQ(a.ring, b.ring) << label;
  EXPECT_EQ(a.return_id, b.return_id) << label;
  EXPECT_EQ(a.stamps, b.stamps) << label;
  EXPECT_EQ(a.start, b.start) << label;
  EXPECT_EQ(a.end, b.end) << label;
  EXPECT_EQ(a.complete, b.complete) << label;
}

void check(const Case& c, ReturnMode returns, const drivers::VelodyneOptions* fov = nullptr) {
  const std::string path = resolve(c.path);
  const std::string label = c.path + " (returns " + std::to_string(static_cast<int>(returns)) + ")";
  auto recording = recording_of(path);
  const io::FirstPackets first = io::first_packets(*recording);
  drivers::DriverOptions options;
  options.scan.returns = returns;
  if (!c.metadata.empty()) options.calibration = kSensors + "/" + c.metadata;
  auto make = [&] {
    return fov ? drivers::make_velodyne_scanner(options, first.packets, *fov)
               : drivers::make_scanner(options, first.packets);
  };

  auto full = make();
  const std::vector<drivers::Scan> scans = decode(*full, *recording);
  ASSERT_GE(scans.size(), 1u) << label;

  auto outliner = make();
  ASSERT_TRUE(outliner->outline_only(true)) << label;
  const std::vector<drivers::Scan> outlines = decode(*outliner, *recording);
  ASSERT_EQ(outlines.size(), scans.size()) << label;
  std::size_t points = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const drivers::Scan &s = scans[i], &o = outlines[i];
    const std::string at = label + " scan " + std::to_string(i);
    EXPECT_EQ(o.outline_points, s.size()) << at;
    EXPECT_EQ(s.outline_points, 0u) << at;
    EXPECT_TRUE(o.xyz.empty() && o.intensity.empty() && o.ring.empty() && o.return_id.empty() &&
                o.stamps.empty())
        << at;
    EXPECT_EQ(o.start, s.start) << at;
    EXPECT_EQ(o.end, s.end) << at;
    EXPECT_EQ(o.first_packet, s.first_packet) << at;
    EXPECT_EQ(o.last_packet, s.last_packet) << at;
    EXPECT_EQ(o.complete, s.complete) << at;
    points += s.size();
  }
  EXPECT_GT(points, 10000u) << label;
  EXPECT_EQ(outliner->describe(), full->describe()) << label;

  // Restarted from the scanner that decoded (and from the outliner): the same scans again.
  for (const drivers::Scanner* from : {full.get(), outliner.get()}) {
    std::unique_ptr<drivers::Scanner> again = from->restart();
    ASSERT_TRUE(again) << label;
    const std::vector<drivers::Scan> rescans = decode(*again, *recording);
    ASSERT_EQ(rescans.size(), scans.size()) << label;
    for (std::size_t i = 0; i < scans.size(); ++i)
      expect_same_points(rescans[i], scans[i], label + " restarted, scan " + std::to_string(i));
    EXPECT_EQ(again->describe(), full->describe()) << label;
  }
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"velodyne/nebula/vls128", ""},
      {"velodyne/nebula/vlp16", ""},  // dual returns
      {"velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap", ""},
      {"hesai/nebula/qt128", ""},
      {"hesai/nebula/40p", ""},
      {"hesai/nebula/xt32m", ""},  // lost packets
      {"ouster/OS-2-128-U1_v2.3.0_1024x10.pcap", "ouster/OS-2-128-U1_v2.3.0_1024x10.json"},
      {"ouster/OS-0-32-U1_v2.2.0_1024x10.pcap", "ouster/OS-0-32-U1_v2.2.0_1024x10.json"},  // dual
      {"ouster/OS-1-64_1024x10_fw20.pcap", "ouster/OS-1-64_sensor_config_reduced.json"},   // LEGACY
  };
  return all;
}

TEST(ScannerOutline, OutlinesAreThoseOfTheDecodedScansAndRestartsDecodeTheSame) {
  if (!fs::exists(kSensors)) GTEST_SKIP() << "no " << kSensors;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.path);
    check(c, ReturnMode::kStrongest);
    check(c, ReturnMode::kAll);
  }
}

TEST(ScannerOutline, VelodyneOutlinesKeepTheFieldOfView) {
  if (!fs::exists(kSensors)) GTEST_SKIP() << "no " << kSensors;
  drivers::VelodyneOptions fov;  // the front half: the outline needs each return's azimuth
  fov.fov_min_deg = 270.0;
  fov.fov_max_deg = 90.0;
  check({"velodyne/nebula/vls128", ""}, ReturnMode::kStrongest, &fov);
  check({"velodyne/nebula/vlp32", ""}, ReturnMode::kStrongest, &fov);
}

}  // namespace
}  // namespace dloam
