// Velodyne decoder: synthetic packets (known returns in, known points out), bad input, and every
// recording of the sensors folder against its reference (VeloView's vlp-16.test, nebula's PCDs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <set>
#include <tuple>

#include "dloam/core/types.hpp"
#include "dloam/drivers/velodyne.hpp"
#include "velodyne_test_util.hpp"

namespace fs = std::filesystem;
using namespace dloam;
using namespace dloam::drivers;
using dloam::test::Recording;
using dloam::test::VelodynePacketBuilder;

namespace {

const std::string kSensors = DLOAM_SENSORS_DIR;
const std::string kVelodyne = kSensors + "/velodyne";
const std::string kCalib = kVelodyne + "/nebula/calibration";
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Packet packet_of(const VelodynePacketBuilder& b, double stamp = 0.0, const std::string& where = "synthetic") {
  Packet p;
  p.data = b.bytes.data();
  p.size = b.bytes.size();
  p.stamp = stamp;
  p.port = kVelodyneDataPort;
  p.where = where;
  return p;
}

/// A VLP-16 stream at `rpm` from azimuth `start` (0.01 deg): n packets, every channel at `raw`.
std::vector<VelodynePacketBuilder> vlp16_stream(int n, double rpm, int start, std::uint16_t raw = 5000,
                                                std::uint32_t toh0 = 1000000) {
  std::vector<VelodynePacketBuilder> out;
  const double units_per_us = rpm / 60.0 * 36000.0 * 1e-6;
  for (int k = 0; k < n; ++k) {
    VelodynePacketBuilder b;
    const double t0 = k * 1327.104;
    for (int blk = 0; blk < 12; ++blk) {
      const auto az = static_cast<int>(std::lround(start + units_per_us * (t0 + blk * 110.592))) % 36000;
      b.block(blk, kVelodyneBank1, static_cast<std::uint16_t>(az));
      for (int c = 0; c < 32; ++c) b.ret(blk, c, raw, 10);
    }
    b.toh(toh0 + static_cast<std::uint32_t>(std::lround(t0))).mode(kVelodyneStrongest).product(0x22);
    out.push_back(b);
  }
  return out;
}

std::vector<Scan> run(Scanner& s, const std::vector<VelodynePacketBuilder>& stream, bool finish = true) {
  std::vector<Scan> done;
  for (std::size_t i = 0; i < stream.size(); ++i)
    s.add(packet_of(stream[i], 1e9 + 1e-3 * static_cast<double>(i), "synthetic packet " + std::to_string(i)),
          done);
  if (finish) s.finish(done);
  return done;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("dloam_velodyne_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

bool have_sensors() { return fs::exists(kVelodyne); }

}  // namespace

// ---------------------------------------------------------------------------------------------
// Synthetic packets

TEST(Velodyne, ChannelDistanceGivesThePointAtTheCalibratedAngle) {
  VelodyneDecoder dec(VelodyneModel::kVLP16, nominal_velodyne_calibration(VelodyneModel::kVLP16));
  VelodynePacketBuilder b;
  b.blocks(kVelodyneBank1, 9000, 0).mode(kVelodyneStrongest).product(0x22).toh(123456);
  b.ret(0, 3, 2500, 77);  // laser 3: +3 deg, 5 m, azimuth 90 deg (no rotation between blocks)
  const auto returns = dec.decode(packet_of(b), 7200.0);
  ASSERT_EQ(returns.size(), 1u);
  const VelodyneReturn& r = returns[0];
  const double d = 2500 * 0.002, w = 3.0 * kDeg, a = 90.0 * kDeg;
  EXPECT_NEAR(r.xyz.x(), d * std::cos(w) * std::cos(a), 1e-9);
  EXPECT_NEAR(r.xyz.y(), -d * std::cos(w) * std::sin(a), 1e-9);  // azimuth 90 = to the right
  EXPECT_NEAR(r.xyz.z(), d * std::sin(w), 1e-9);
  EXPECT_FLOAT_EQ(r.intensity, 77.0f);
  EXPECT_EQ(r.laser, 3);
  EXPECT_EQ(r.ring, 9);  // -15 -13 -11 -9 -7 -5 -3 -1 1 3: ninth from the bottom, 0-based
  EXPECT_NEAR(r.time, 7200.0 + 0.123456 + 3 * 2.304e-6, 1e-9);
}

TEST(Velodyne, FiringTimesFollowTheManualsTables) {
  struct Case {
    VelodyneModel model;
    std::uint16_t flag_of_block[12];
    std::uint8_t mode;
    int block, channel;
    double offset_us;  // firing time after the TOH
  };
  const std::uint16_t E = kVelodyneBank1, D = kVelodyneBank2, C = kVelodyneBank3, B = kVelodyneBank4;
  const Case cases[] = {
      // VLP-16: 55.296 us * sequence + 2.304 us * laser; two sequences per block.
      {VelodyneModel::kVLP16,
       {E, E, E, E, E, E, E, E, E, E, E, E},
       kVelodyneStrongest,
       5,
       20,
       55.296 * 11 + 2.304 * 4},
      {VelodyneModel::kVLP16,
       {E, E, E, E, E, E, E, E, E, E, E, E},
       kVelodyneDual,
       5,
       20,
       55.296 * 5 + 2.304 * 4},
      // VLP-32C: laser pairs 2.304 us apart, 55.296 us per block.
      {VelodyneModel::kVLP32C,
       {E, E, E, E, E, E, E, E, E, E, E, E},
       kVelodyneStrongest,
       3,
       7,
       55.296 * 3 + 2.304 * 3},
      {VelodyneModel::kVLP32C,
       {E, E, E, E, E, E, E, E, E, E, E, E},
       kVelodyneDual,
       3,
       7,
       55.296 * 1 + 2.304 * 3},
      // HDL-32E: -542.592 + 46.08 * block + 1.152 * laser (the TOH is at the end of the packet).
      {VelodyneModel::kHDL32E,
       {E, E, E, E, E, E, E, E, E, E, E, E},
       kVelodyneStrongest,
       11,
       31,
       -542.592 + 46.08 * 11 + 1.152 * 31},
      // VLS-128: 53.3 us sequences of 16 groups of 8 lasers 2.665 us apart, a maintenance slot
      // after group 8, the TOH 8.7 us after the first firing.
      {VelodyneModel::kVLS128,
       {E, D, C, B, E, D, C, B, E, D, C, B},
       kVelodyneStrongest,
       6,
       5,
       -8.7 + 53.3 * 1 + 2.665 * (8 + 1)},
      // HDL-64E S2: upper and lower lasers together, 0.728 us apart, first firing 419.30 us before.
      {VelodyneModel::kHDL64E_S2,
       {E, D, E, D, E, D, E, D, E, D, E, D},
       kVelodyneStrongest,
       5,
       9,
       -419.30 + 23.296 * 2 + 0.728 * 9},
  };
  for (const Case& c : cases) {
    VelodyneCalibration cal = c.model == VelodyneModel::kHDL64E_S2
                                  ? read_velodyne_calibration(kCalib + "/HDL64e_s2.yaml")
                                  : nominal_velodyne_calibration(c.model);
    if (c.model == VelodyneModel::kHDL64E_S2 && !have_sensors()) continue;
    ScannerOptions so;
    so.returns = ReturnMode::kAll;
    VelodyneDecoder dec(c.model, cal, so);
    VelodynePacketBuilder b;
    for (int blk = 0; blk < 12; ++blk) b.block(blk, c.flag_of_block[blk], 1000);
    b.ret(c.block, c.channel, 3000, 1).mode(c.mode).toh(500000);
    const auto r = dec.decode(packet_of(b), 0.0);
    ASSERT_EQ(r.size(), 1u) << velodyne_model_name(c.model);
    EXPECT_NEAR((r[0].time - 0.5) * 1e6, c.offset_us, 1e-4)
        << velodyne_model_name(c.model) << " mode " << int(c.mode);
  }
}

TEST(Velodyne, AzimuthIsInterpolatedOverTheFiringTime) {
  VelodyneDecoder dec(VelodyneModel::kVLP16, nominal_velodyne_calibration(VelodyneModel::kVLP16));
  VelodynePacketBuilder b;
  b.blocks(kVelodyneBank1, 1000, 96).mode(kVelodyneStrongest);  // 0.96 deg per 110.592 us block
  b.ret(2, 0, 1000, 1).ret(2, 16, 1000, 1).ret(2, 24, 1000, 1).ret(11, 16, 1000, 1);
  const auto r = dec.decode(packet_of(b), 0.0);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].azimuth, 1000 + 2 * 96);
  EXPECT_EQ(r[1].azimuth, 1000 + 2 * 96 + 48);   // second sequence, half a block later
  EXPECT_EQ(r[2].azimuth, 1000 + 2 * 96 + 64);   // 55.296 + 8 * 2.304 = 2/3 of the block
  EXPECT_EQ(r[3].azimuth, 1000 + 11 * 96 + 48);  // the last block rotates as the one before
  // The point lies at its azimuth: azimuth = atan2(-y, x) (float cos / sin table: 1e-7 rad).
  EXPECT_NEAR(std::atan2(-r[1].xyz.y(), r[1].xyz.x()) / kDeg, (1000 + 2 * 96 + 48) * 0.01, 1e-5);
}

TEST(Velodyne, DualReturnsKeepStrongestLastOrBothAndIdenticalOnce) {
  VelodynePacketBuilder b;
  b.blocks(kVelodyneBank1, 500, 0).mode(kVelodyneDual).product(0x22);
  // Block 0 = last return, block 1 = strongest (or second strongest).
  b.ret(0, 0, 4000, 20).ret(1, 0, 2000, 90);  // strongest nearer than the last
  b.ret(0, 1, 3000, 60).ret(1, 1, 1500, 30);  // the last is the strongest: block 1 = second strongest
  b.ret(0, 2, 2500, 40).ret(1, 2, 2500, 40);  // one return, reported in both blocks
  b.ret(2, 3, 1000, 5);                       // a second pair: only the last block has it
  auto decode = [&](ReturnMode m) {
    ScannerOptions so;
    so.returns = m;
    VelodyneDecoder dec(VelodyneModel::kVLP16, nominal_velodyne_calibration(VelodyneModel::kVLP16), so);
    return dec.decode(packet_of(b), 0.0);
  };
  const auto all = decode(ReturnMode::kAll);
  ASSERT_EQ(all.size(), 6u);
  EXPECT_EQ(all[0].raw_distance, 2000);
  EXPECT_EQ(all[0].return_id, 0);
  EXPECT_EQ(all[1].raw_distance, 4000);
  EXPECT_EQ(all[1].return_id, 1);
  EXPECT_EQ(all[2].raw_distance, 1500);
  EXPECT_EQ(all[3].raw_distance, 3000);
  EXPECT_EQ(all[4].raw_distance, 2500);  // identical returns: once
  EXPECT_EQ(all[4].return_id, 0);
  EXPECT_EQ(all[5].raw_distance, 1000);
  // Both returns of a pair share the firing: same time, same azimuth.
  EXPECT_EQ(all[0].time, all[1].time);
  EXPECT_EQ(all[0].azimuth, all[1].azimuth);
  // Pair (2, 3) is 110.592 us after pair (0, 1): dual packets hold 6 firing pairs.
  EXPECT_NEAR((all[5].time - all[0].time) * 1e6, 110.592 + 3 * 2.304, 1e-6);

  const auto strongest = decode(ReturnMode::kStrongest);
  ASSERT_EQ(strongest.size(), 4u);
  EXPECT_EQ(strongest[0].raw_distance, 2000);
  EXPECT_EQ(strongest[1].raw_distance, 3000);
  EXPECT_EQ(strongest[2].raw_distance, 2500);
  const auto last = decode(ReturnMode::kLast);
  ASSERT_EQ(last.size(), 4u);
  EXPECT_EQ(last[0].raw_distance, 4000);
  EXPECT_EQ(last[1].raw_distance, 3000);
  EXPECT_NE(error_of([&] { decode(ReturnMode::kFirst); }).find("not the first"), std::string::npos);
}

TEST(Velodyne, ScansAreCutWhereTheAzimuthPassesTheCutAngle) {
  // 600 rpm, from 300 deg: 75.4 packets per turn.
  const auto stream = vlp16_stream(200, 600.0, 30000);
  for (double cut : {0.0, 180.0}) {
    DriverOptions o;
    o.model = "VLP-16";
    o.scan.cut_azimuth_deg = cut;
    auto s = make_velodyne_scanner(o, {});
    const auto scans = run(*s, stream);
    ASSERT_GE(scans.size(), 3u);
    EXPECT_FALSE(scans.front().complete);
    EXPECT_FALSE(scans.back().complete);
    for (std::size_t k = 1; k + 1 < scans.size(); ++k) {
      const Scan& sc = scans[k];
      EXPECT_TRUE(sc.complete) << "cut " << cut << " scan " << k;
      // One turn: 1808 firing sequences of 16 lasers at 600 rpm.
      EXPECT_NEAR(static_cast<double>(sc.size()), 1808.4 * 16, 3 * 16.0);
      EXPECT_NEAR(sc.end - sc.start, 0.1, 2e-4);
      // Every point's azimuth lies in the turn that starts at the cut.
      const double first =
          std::fmod(std::atan2(-sc.xyz.front().y(), sc.xyz.front().x()) / kDeg - cut + 720.0, 360.0);
      const double last =
          std::fmod(std::atan2(-sc.xyz.back().y(), sc.xyz.back().x()) / kDeg - cut + 720.0, 360.0);
      EXPECT_LT(first, 1.0);
      // Firing groups are whole: the last group's later firings may reach past the cut by less
      // than a block's rotation (0.4 deg at 600 rpm).
      EXPECT_TRUE(last > 359.0 || last < 0.4) << last;
      EXPECT_TRUE(std::is_sorted(sc.stamps.begin(), sc.stamps.end()));
    }
    // Nothing is lost or repeated.
    std::size_t total = 0;
    for (const Scan& sc : scans) total += sc.size();
    EXPECT_EQ(total, 200u * 384u);
  }
}

TEST(Velodyne, LostPacketsMakeTheScanIncompleteAndALimitedFieldOfViewDoesNot) {
  auto stream = vlp16_stream(300, 600.0, 1000);
  // Drop 10 packets in the middle of the third turn.
  std::vector<VelodynePacketBuilder> lossy(stream.begin(), stream.begin() + 190);
  lossy.insert(lossy.end(), stream.begin() + 200, stream.end());
  DriverOptions o;
  o.model = "VLP-16";
  auto s = make_velodyne_scanner(o, {});
  auto scans = run(*s, lossy);
  ASSERT_EQ(scans.size(), 5u);
  EXPECT_TRUE(scans[1].complete);
  EXPECT_FALSE(scans[2].complete);  // holds the gap
  EXPECT_TRUE(scans[3].complete);

  // A sensor that sends only 270 -> 90 deg: the gap is outside its field of view.
  std::vector<VelodynePacketBuilder> window;
  for (const auto& p : stream) {
    const int az = p.bytes[2] | (p.bytes[3] << 8);
    if (az >= 27000 || az <= 8800) window.push_back(p);
  }
  VelodyneOptions fov;
  fov.fov_min_deg = 270.0;
  fov.fov_max_deg = 90.0;
  o.scan.cut_azimuth_deg = 180.0;
  auto limited = make_velodyne_scanner(o, {}, fov);
  scans = run(*limited, window);
  ASSERT_GE(scans.size(), 3u);
  EXPECT_FALSE(scans[0].complete);  // the recording starts at 10 deg, inside the window
  for (std::size_t k = 1; k + 1 < scans.size(); ++k)
    EXPECT_TRUE(scans[k].complete) << k << " of " << scans.size() << ": " << scans[k].size()
                                   << " points, packets " << scans[k].first_packet << "-"
                                   << scans[k].last_packet;
  for (const Vec3& p : scans[1].xyz) {
    const double az = std::fmod(std::atan2(-p.y(), p.x()) / kDeg + 360.0, 360.0);
    EXPECT_TRUE(az >= 270.0 || az <= 90.0) << az;
  }
  // Without the field of view the missing half is lost data.
  o.scan.cut_azimuth_deg = 180.0;
  auto full = make_velodyne_scanner(o, {});
  scans = run(*full, window);
  for (const Scan& sc : scans) EXPECT_FALSE(sc.complete);
}

TEST(Velodyne, PositionPacketsAreCountedAndIgnored) {
  DriverOptions o;
  o.model = "VLP-16";
  auto s = make_velodyne_scanner(o, {});
  std::vector<Scan> done;
  std::vector<std::uint8_t> pos(512, 0);
  Packet p;
  p.data = pos.data();
  p.size = pos.size();
  p.port = kVelodynePositionPort;
  s->add(p, done);
  p.port = 0;  // from a bag: no port, still 512 bytes
  s->add(p, done);
  EXPECT_TRUE(done.empty());
  EXPECT_NE(s->describe().find("2 position packets ignored"), std::string::npos) << s->describe();
  std::vector<std::uint8_t> odd(600, 0);
  p.data = odd.data();
  p.size = odd.size();
  p.port = kVelodynePositionPort;
  p.where = "x.pcap: datagram 9";
  EXPECT_NE(error_of([&] { s->add(p, done); }).find("x.pcap: datagram 9"), std::string::npos);
}

TEST(Velodyne, SensorModelComesFromTheCalibrationAndTheMeasuredRotation) {
  DriverOptions o;
  o.model = "VLP-16";
  auto s = make_velodyne_scanner(o, {});
  run(*s, vlp16_stream(100, 600.0, 0), false);
  const SensorConfig c = s->sensor();
  EXPECT_EQ(c.preset, "VLP-16");
  EXPECT_EQ(c.N_scan, 16);
  ASSERT_EQ(c.beam_elevations_deg.size(), 16u);
  EXPECT_TRUE(std::is_sorted(c.beam_elevations_deg.begin(), c.beam_elevations_deg.end()));
  EXPECT_NEAR(c.beam_elevations_deg.front(), -15.0, 1e-9);
  EXPECT_NEAR(c.beam_elevations_deg.back(), 15.0, 1e-9);
  EXPECT_TRUE(c.beam_vertical_offsets_m.empty());
  EXPECT_NEAR(c.scan_rate_hz, 10.0, 0.02);
  EXPECT_EQ(c.Horizon_SCAN, 1792);  // 1808 firings per turn, rounded down to a multiple of 64
  EXPECT_NO_THROW(c.validate());

  auto fast = make_velodyne_scanner(o, {});
  run(*fast, vlp16_stream(100, 1200.0, 0), false);
  EXPECT_NEAR(fast->sensor().scan_rate_hz, 20.0, 0.04);
  EXPECT_EQ(fast->sensor().Horizon_SCAN, 896);

  if (!have_sensors()) return;
  // HDL-64E: beam origin heights from vert_offset_correction, bottom beam first.
  o.model = "HDL-64E S2";
  o.calibration = kCalib + "/HDL64e_s2.yaml";
  const SensorConfig h = make_velodyne_scanner(o, {})->sensor();
  ASSERT_EQ(h.beam_vertical_offsets_m.size(), 64u);
  const VelodyneCalibration cal = read_velodyne_calibration(o.calibration);
  for (const VelodyneLaser& l : cal.lasers) {
    EXPECT_NEAR(h.beam_elevations_deg[static_cast<std::size_t>(l.ring)], l.vert_correction / kDeg, 1e-9);
    EXPECT_EQ(h.beam_vertical_offsets_m[static_cast<std::size_t>(l.ring)], l.vert_offset_correction);
  }
}

TEST(Velodyne, Hdl64eUsesTheRosDriversCorrectionModel) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  const VelodyneCalibration cal = read_velodyne_calibration(kCalib + "/HDL64e_s2.yaml");
  VelodyneDecoder dec(VelodyneModel::kHDL64E_S2, cal);
  VelodynePacketBuilder b;
  for (int blk = 0; blk < 12; ++blk) b.block(blk, blk % 2 ? kVelodyneBank2 : kVelodyneBank1, 4500);
  b.ret(1, 5, 10000, 100);  // lower block: laser 37
  const auto r = dec.decode(packet_of(b), 0.0);
  ASSERT_EQ(r.size(), 1u);
  const VelodyneLaser& l = cal.lasers[37];
  EXPECT_EQ(r[0].laser, 37);
  // The correction model written out: distance correction, beam origin offsets, azimuth - rot.
  const double d = 10000 * 0.002 + l.dist_correction;
  const double a = std::lround(4500 - l.rot_correction / kDeg * 100.0) * 0.01 * kDeg;
  const double cw = std::cos(l.vert_correction), sw = std::sin(l.vert_correction);
  const double xy = d * cw - l.vert_offset_correction * sw;
  const double vx = xy * std::sin(a) - l.horiz_offset_correction * std::cos(a);
  const double vy = xy * std::cos(a) + l.horiz_offset_correction * std::sin(a);
  EXPECT_NEAR(r[0].xyz.x(), vy, 1e-5);
  EXPECT_NEAR(r[0].xyz.y(), -vx, 1e-5);
  EXPECT_NEAR(r[0].xyz.z(), d * sw + l.vert_offset_correction * cw, 1e-5);
  EXPECT_NEAR(r[0].range, d, 1e-5);
}

// ---------------------------------------------------------------------------------------------
// Calibration files and bad input

TEST(Velodyne, CalibrationYamlAndVeloViewXmlGiveTheSameVlp16) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  const VelodyneCalibration yaml = read_velodyne_calibration(kCalib + "/VLP16.yaml");
  const VelodyneCalibration xml = read_velodyne_calibration(kVelodyne + "/veloview/VLP-16.xml");
  const VelodyneCalibration nominal = nominal_velodyne_calibration(VelodyneModel::kVLP16);
  ASSERT_EQ(yaml.size(), 16);
  ASSERT_EQ(xml.size(), 16);  // 64 entries, 16 enabled
  EXPECT_DOUBLE_EQ(yaml.distance_resolution, 0.002);
  EXPECT_DOUBLE_EQ(xml.distance_resolution, 0.002);
  for (int i = 0; i < 16; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_NEAR(yaml.lasers[k].vert_correction, xml.lasers[k].vert_correction, 1e-12);
    EXPECT_NEAR(yaml.lasers[k].vert_correction, nominal.lasers[k].vert_correction, 1e-12);
    EXPECT_EQ(yaml.lasers[k].ring, xml.lasers[k].ring);
  }
  for (const char* f : {"HDL32.yaml", "VLP32.yaml", "VLS128.yaml"}) {
    const VelodyneCalibration c = read_velodyne_calibration(kCalib + "/" + f);
    const VelodyneModel m = c.size() == 128 ? VelodyneModel::kVLS128
                            : f[0] == 'H'   ? VelodyneModel::kHDL32E
                                            : VelodyneModel::kVLP32C;
    const VelodyneCalibration n = nominal_velodyne_calibration(m);
    ASSERT_EQ(c.size(), n.size()) << f;
    for (std::size_t i = 0; i < c.lasers.size(); ++i) {
      EXPECT_NEAR(c.lasers[i].vert_correction / kDeg, n.lasers[i].vert_correction / kDeg, 0.006)
          << f << " " << i;
      EXPECT_NEAR(c.lasers[i].rot_correction / kDeg, n.lasers[i].rot_correction / kDeg, 0.006)
          << f << " " << i;
    }
  }
}

TEST(Velodyne, BadCalibrationFilesNameTheFileAndTheKey) {
  const std::string laser =
      "  - {laser_id: 0, rot_correction: 0.0, vert_correction: 0.1, dist_correction: 0.0, "
      "vert_offset_correction: 0.0}\n";
  const std::string missing = write_temp(
      "missing.yaml",
      "lasers:\n  - {laser_id: 0, rot_correction: 0.0, dist_correction: 0.0, vert_offset_correction: 0.0}\n");
  std::string e = error_of([&] { read_velodyne_calibration(missing); });
  EXPECT_NE(e.find(missing), std::string::npos) << e;
  EXPECT_NE(e.find("lasers[0]: missing key 'vert_correction'"), std::string::npos) << e;

  const std::string count = write_temp("count.yaml", "num_lasers: 16\nlasers:\n" + laser);
  e = error_of([&] { read_velodyne_calibration(count); });
  EXPECT_NE(e.find("num_lasers is 16 but 'lasers' lists 1"), std::string::npos) << e;

  const std::string no_lasers = write_temp("nolasers.yaml", "num_lasers: 16\n");
  EXPECT_NE(error_of([&] { read_velodyne_calibration(no_lasers); }).find("missing key 'lasers'"),
            std::string::npos);
  const std::string not_number = write_temp("nan.yaml",
                                            "lasers:\n  - {laser_id: 0, rot_correction: x, vert_correction: "
                                            "0.1, dist_correction: 0.0, vert_offset_correction: 0.0}\n");
  EXPECT_NE(error_of([&] {
              read_velodyne_calibration(not_number);
            }).find("lasers[0].rot_correction is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_velodyne_calibration("/no/such/VLP16.yaml"); }).find("/no/such/VLP16.yaml"),
            std::string::npos);

  // Numbers far outside any integer or angle are refused by name, in both formats.
  const std::string huge_count = write_temp("hugecount.yaml", "num_lasers: 1e300\nlasers:\n" + laser);
  e = error_of([&] { read_velodyne_calibration(huge_count); });
  EXPECT_NE(e.find("num_lasers is 1e+300 but 'lasers' lists 1"), std::string::npos) << e;
  const std::string huge_rot =
      write_temp("hugerot.yaml",
                 "lasers:\n  - {laser_id: 0, rot_correction: 1e300, vert_correction: 0.1, dist_correction: "
                 "0.0, vert_offset_correction: 0.0}\n");
  e = error_of([&] { read_velodyne_calibration(huge_rot); });
  EXPECT_NE(e.find(huge_rot + ": laser 0: rotational correction"), std::string::npos) << e;
  const std::string px =
      "<px><id_>ID</id_><rotCorrection_>ROT</rotCorrection_><vertCorrection_>-15"
      "</vertCorrection_><distCorrection_>0</distCorrection_><distCorrectionX_>0"
      "</distCorrectionX_><distCorrectionY_>0</distCorrectionY_><vertOffsetCorrection_>0"
      "</vertOffsetCorrection_><horizOffsetCorrection_>0</horizOffsetCorrection_>"
      "<focalDistance_>0</focalDistance_><focalSlope_>0</focalSlope_></px>";
  auto xml_with = [&](const std::string& name, const std::string& id, const std::string& rot) {
    std::string item = px;
    item.replace(item.find("ID"), 2, id);
    item.replace(item.find("ROT"), 3, rot);
    return write_temp(name, "<DB><points_><item>" + item + "</item></points_></DB>\n");
  };
  EXPECT_EQ(read_velodyne_calibration(xml_with("good.xml", "0", "1.5")).size(), 1);
  for (const char* id : {"1e30", "-1e30", "0.5", "1"}) {
    const std::string bad_id = xml_with("badid.xml", id, "0");
    e = error_of([&] { read_velodyne_calibration(bad_id); });
    EXPECT_NE(e.find(bad_id + ": points_ item 0: id_ "), std::string::npos) << id << ": " << e;
    EXPECT_NE(e.find(" is not in 0..0"), std::string::npos) << id << ": " << e;
  }
  const std::string bad_rot = xml_with("badrot.xml", "0", "400");
  e = error_of([&] { read_velodyne_calibration(bad_rot); });
  EXPECT_NE(e.find("laser 0: rotational correction 400.000000 deg is not an azimuth offset (the file is in "
                   "degrees)"),
            std::string::npos)
      << e;

  // A calibration with the wrong number of lasers for the model.
  const std::string one = write_temp("one.yaml", "lasers:\n" + laser);
  DriverOptions o;
  o.model = "VLP-16";
  o.calibration = one;
  e = error_of([&] { make_velodyne_scanner(o, {}); });
  EXPECT_NE(e.find(one + ": the calibration has 1 lasers, the VLP-16 packets need 16"), std::string::npos)
      << e;
  if (!have_sensors()) return;
  // 16 lasers for HDL-32E packets (the model told by the packets).
  const Recording hdl = test::read_pcap(kVelodyne + "/rust-lidar-utils/hdl32_example.pcap");
  o.model.clear();
  o.calibration = kCalib + "/VLP16.yaml";
  e = error_of([&] { make_velodyne_scanner(o, hdl.first(40)); });
  EXPECT_NE(e.find("VLP16.yaml: the calibration has 16 lasers, the HDL-32E packets need 32"),
            std::string::npos)
      << e;
  // The HDL-64E has no nominal table.
  o.model = "HDL-64E S3";
  o.calibration.clear();
  e = error_of([&] { make_velodyne_scanner(o, {}); });
  EXPECT_NE(e.find("HDL-64E S3 packets need the unit's own calibration file"), std::string::npos) << e;
}

TEST(Velodyne, BadPacketsNameThePacketAndTheProblem) {
  DriverOptions o;
  o.model = "VLP-16";
  auto s = make_velodyne_scanner(o, {});
  std::vector<Scan> done;
  std::vector<std::uint8_t> small(1000, 0);
  Packet p;
  p.data = small.data();
  p.size = small.size();
  p.where = "drive.pcap: datagram 7";
  std::string e = error_of([&] { s->add(p, done); });
  EXPECT_NE(e.find("drive.pcap: datagram 7: not a Velodyne packet: 1000 bytes"), std::string::npos) << e;

  VelodynePacketBuilder b;
  b.blocks(kVelodyneBank1, 0, 20).mode(kVelodyneStrongest);
  b.block(4, 0x1234, 80);
  EXPECT_FALSE(looks_like_velodyne(packet_of(b)));
  e = error_of([&] { s->add(packet_of(b, 0.0, "drive.pcap: datagram 8"), done); });
  EXPECT_NE(e.find("drive.pcap: datagram 8: block 4 has flag 0x1234"), std::string::npos) << e;

  b.blocks(kVelodyneBank1, 0, 20).mode(0x41);
  e = error_of([&] { s->add(packet_of(b, 0.0, "p9"), done); });
  EXPECT_NE(e.find("p9: unknown return mode byte 0x41"), std::string::npos) << e;
  b.mode(kVelodyneStrongest).block(3, kVelodyneBank1, 36500);
  e = error_of([&] { s->add(packet_of(b, 0.0, "p10"), done); });
  EXPECT_NE(e.find("p10: block 3 azimuth 36500"), std::string::npos) << e;

  // VLS-128 packets given as a VLP-16.
  VelodynePacketBuilder v;
  for (int blk = 0; blk < 12; ++blk)
    v.block(
        blk,
        std::array<std::uint16_t, 4>{kVelodyneBank1, kVelodyneBank2, kVelodyneBank3, kVelodyneBank4}[blk % 4],
        100);
  v.mode(kVelodyneStrongest).product(0xA1);
  std::vector<Packet> first = {packet_of(v, 0.0, "v0")};
  e = error_of([&] { make_velodyne_scanner(o, first); });
  EXPECT_NE(e.find("v0: model VLP-16 was given, but the packet has four laser banks"), std::string::npos)
      << e;
  o.model = "VLP-99";
  EXPECT_NE(error_of([&] { make_velodyne_scanner(o, first); }).find("unknown Velodyne model 'VLP-99'"),
            std::string::npos);

  // Unknown product, one packet (no timing), too few returns to see the channel structure.
  VelodynePacketBuilder u;
  u.blocks(kVelodyneBank1, 0, 20).mode(kVelodyneStrongest).product(0x99);
  o.model.clear();
  e = error_of([&] { make_velodyne_scanner(o, {packet_of(u, 0.0, "u0")}); });
  EXPECT_NE(e.find("u0: unknown Velodyne product byte 0x99"), std::string::npos) << e;
  EXPECT_NE(e.find("set the model"), std::string::npos) << e;
  e = error_of([&] { make_velodyne_scanner(o, {}); });
  EXPECT_NE(e.find("no Velodyne data packet"), std::string::npos) << e;
}

// ---------------------------------------------------------------------------------------------
// Recordings

TEST(Velodyne, RustLidarUtilsPcapsAreIdentifiedAndDecoded) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  struct Case {
    const char* file;
    VelodyneModel model;
    double rpm;
    std::size_t full_turns;
  };
  // Sensor, speed and turns as measured independently in the sensors README.
  const Case cases[] = {{"hdl32_example.pcap", VelodyneModel::kHDL32E, 704, 5},
                        {"velodyne_example.pcap", VelodyneModel::kVLP16, 600, 0},
                        {"velodyne_vlp16.pcap", VelodyneModel::kVLP16, 600, 0},    // product byte 0x21
                        {"velodyne_vlp32.pcap", VelodyneModel::kHDL32E, 704, 0}};  // HDL-32E data
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const Recording rec = test::read_pcap(kVelodyne + "/rust-lidar-utils/" + c.file);
    std::uint32_t prev = 0;
    std::size_t data = 0;
    for (std::size_t i = 0; i < rec.size(); ++i) {
      const Packet p = rec.packet(i);
      if (!looks_like_velodyne(p)) continue;
      const std::uint32_t toh = velodyne_packet_header(p).toh_us;
      if (data++ > 0) {
        EXPECT_GT(toh, prev) << i;  // upstream's only check: TOH increases
      }
      prev = toh;
    }
    EXPECT_EQ(identify_velodyne(rec.first(40)).model, c.model) << identify_velodyne(rec.first(40)).evidence;
    DriverOptions o;
    auto s = make_velodyne_scanner(o, rec.first(40));
    std::vector<Scan> scans;
    for (std::size_t i = 0; i < rec.size(); ++i) s->add(rec.packet(i), scans);
    s->finish(scans);
    EXPECT_EQ(static_cast<std::size_t>(
                  std::count_if(scans.begin(), scans.end(), [](const Scan& x) { return x.complete; })),
              c.full_turns);
    EXPECT_NEAR(s->sensor().scan_rate_hz * 60.0, c.rpm, 0.02 * c.rpm);
    EXPECT_EQ(s->sensor().N_scan, velodyne_model_info(c.model).lasers);
    for (const Scan& sc : scans) {
      EXPECT_TRUE(std::is_sorted(sc.stamps.begin(), sc.stamps.end()));
      for (std::size_t k = 0; k < sc.size(); ++k) {
        ASSERT_TRUE(sc.xyz[k].allFinite());
        ASSERT_LT(sc.ring[k], s->sensor().N_scan);
        ASSERT_LT(sc.xyz[k].norm(), 140.0);
      }
    }
  }
}

TEST(Velodyne, VeloViewVlp16TestExpectations) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  const Recording rec = test::read_pcap(kVelodyne + "/veloview/vlp-16-test-90deg-1-50-frames.pcap");
  const VelodyneIdentification id = identify_velodyne(rec.first(50));
  EXPECT_EQ(id.model, VelodyneModel::kVLP16) << id.evidence;  // although the product byte says 0x21
  // VeloView's reader of vlp-16.test: every non-zero return, a new frame where a block's azimuth
  // drops below the previous block's, frames 0 and 51 partial.
  DriverOptions o;
  o.calibration = kVelodyne + "/veloview/VLP-16.xml";
  o.scan.min_range = 0.001;
  o.scan.max_range = 200.0;
  auto s = make_velodyne_scanner(o, rec.first(50));
  std::vector<Scan> frames;
  for (std::size_t i = 0; i < rec.size(); ++i) s->add(rec.packet(i), frames);
  s->finish(frames);
  EXPECT_NE(s->describe().find("367 position packets ignored"), std::string::npos) << s->describe();
  ASSERT_EQ(frames.size(), 52u);
  EXPECT_EQ(frames[0].size(), 5736u);
  EXPECT_EQ(frames[2].size(), 13898u);
  EXPECT_EQ(frames[16].size(), 13860u);
  EXPECT_EQ(frames[51].size(), 274u);
  EXPECT_FALSE(frames[0].complete);
  EXPECT_FALSE(frames[51].complete);
  for (std::size_t k = 1; k <= 50; ++k) EXPECT_TRUE(frames[k].complete) << k;
  // point_values id x y z intensity, in VeloView's axes: x_vv = -y_ros, y_vv = x_ros.
  struct Expect {
    std::size_t id;
    double x, y, z, intensity;
  };
  for (const Expect& e :
       {Expect{0, 0.0801272, 6.04037, -1.61865, 4}, Expect{13859, -0.0094354, 4.91462, 1.31687, 29}}) {
    const Vec3& p = frames[16].xyz[e.id];
    EXPECT_NEAR(-p.y(), e.x, 1e-4) << e.id;
    EXPECT_NEAR(p.x(), e.y, 1e-4) << e.id;
    EXPECT_NEAR(p.z(), e.z, 1e-4) << e.id;
    EXPECT_NEAR(frames[16].intensity[e.id], e.intensity, 1e-4) << e.id;
  }
}

// ---------------------------------------------------------------------------------------------
// nebula references

namespace {

/// nebula's decoders, as the sensors README describes them, replayed over this decoder's returns:
/// which returns a nebula scan holds and at which (rounded) azimuth nebula puts them. Only the
/// azimuth and the membership rules are nebula's; distances, angles and times are this decoder's.
struct NebulaReturn {
  VelodyneReturn r;
  std::size_t packet = 0;
  int azimuth = 0;        ///< nebula's corrected azimuth (0.01 deg)
  int block_azimuth = 0;  ///< the azimuth nebula gives the block
};

struct NebulaRules {
  VelodyneModel model;
  double phase_deg;
  bool cloud_0_359;    ///< VLP16 / VLS128 checks: block and point azimuth <= 359 deg
  bool window_270_90;  ///< VLP32 check: raw block azimuth in 270 -> 90
  bool move_trailing;  ///< the completing packet's trailing points with azimuth < 90 deg move on
};

int nebula_azimuth(const NebulaRules& rules, const Packet& p, const VelodyneReturn& r,
                   const VelodyneCalibration& cal, int& block_az) {
  auto az = [&](int b) { return static_cast<int>(p.data[b * 100 + 2] | (p.data[b * 100 + 3] << 8)); };
  const bool dual = p.data[1204] == kVelodyneDual;
  const int b = r.block;
  float diff = 0.0f;
  int a = az(b);
  if (dual && rules.model == VelodyneModel::kVLP16) {
    // Odd blocks take the next pair's azimuth (its own for block 11) and no interpolation;
    // block 10 is not interpolated.
    if (b % 2 == 1) {
      a = b < 11 ? az(b + 1) : az(11);
    } else if (b < 10) {
      diff = static_cast<float>((az(b + 2) - az(b) + 36000) % 36000);
    }
  } else if (b < 11) {
    diff = static_cast<float>((az(b + 1) - az(b) + 36000) % 36000);  // block 11: none
  }
  block_az = a;
  float interp = 0.0f;
  const int j = r.channel;
  switch (rules.model) {
    case VelodyneModel::kVLP16:
      interp = (diff * ((static_cast<float>(j % 16) * 2.304f) + (static_cast<float>(j / 16) * 55.296f))) /
               110.592f;
      break;
    case VelodyneModel::kVLP32C:
      interp = diff * 2.304f / 55.296f * static_cast<float>(j);  // the channel, not its firing pair
      break;
    default: {
      const int g = r.laser / 8;
      interp = diff * ((2.665f / 53.3f) * static_cast<float>(g + g / 8));
    }
  }
  const auto rot = static_cast<float>(cal.lasers[r.laser].rot_correction);
  float corrected =
      static_cast<float>(static_cast<double>(static_cast<float>(a) + interp) - rot * 180.0 / kPi * 100);
  if (corrected < 0.0f) corrected = static_cast<float>(corrected + 36000.0);
  return static_cast<int>(std::round(corrected)) % 36000;
}

struct NebulaScan {
  std::size_t completing_packet = 0;
  std::vector<NebulaReturn> points;
};

std::vector<NebulaScan> nebula_scans(const NebulaRules& rules, const Recording& rec,
                                     const VelodyneCalibration& cal, double min_range, double max_range,
                                     std::vector<NebulaReturn>* every = nullptr) {
  ScannerOptions so;
  so.returns = ReturnMode::kAll;
  so.min_range = min_range;
  so.max_range = max_range;
  VelodyneDecoder dec(rules.model, cal, so);
  const int phase = static_cast<int>(std::lround(rules.phase_deg * 100));
  std::vector<NebulaScan> out;
  std::vector<NebulaReturn> scan, overflow;
  bool scanned = false;
  std::size_t processed = 0;
  int prev_first = 0;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Packet p = rec.packet(i);
    if (scanned) {
      processed = 0;
      scan = overflow;
      overflow.clear();
    }
    ++processed;
    const int first = (36000 + (p.data[2] | (p.data[3] << 8)) - phase) % 36000;
    const int last = (36000 + (p.data[1102] | (p.data[1103] << 8)) - phase) % 36000;
    scanned = processed > 1 && (last < first || first < prev_first);
    prev_first = first;
    std::vector<VelodyneReturn> rs = dec.decode(p, 0.0);
    std::stable_sort(rs.begin(), rs.end(), [](const VelodyneReturn& x, const VelodyneReturn& y) {
      return std::tie(x.block, x.channel) < std::tie(y.block, y.channel);
    });
    for (const VelodyneReturn& r : rs) {
      NebulaReturn n{r, i, 0, 0};
      n.azimuth = nebula_azimuth(rules, p, r, cal, n.block_azimuth);
      if (every) every->push_back(n);
      if (rules.cloud_0_359 && (n.block_azimuth > 35900 || n.azimuth > 35900)) continue;
      const int raw_block = p.data[r.block * 100 + 2] | (p.data[r.block * 100 + 3] << 8);
      if (rules.window_270_90 && !(raw_block <= 9000 || raw_block >= 27000)) continue;
      scan.push_back(n);
    }
    if (scanned) {
      if (rules.move_trailing) {
        auto quarter = [&](int a) {
          const auto rad = static_cast<float>(0.01 * a * kPi / 180.0);
          const double deg = (2 * kPi + rad - rules.phase_deg * kDeg) * 180.0 / kPi;
          return static_cast<std::size_t>(deg) % 360 < 90;
        };
        while (!scan.empty() && quarter(scan.back().azimuth)) {
          overflow.insert(overflow.begin(), scan.back());
          scan.pop_back();
        }
      }
      out.push_back({i, scan});
    }
  }
  return out;
}

bool fov_contains(const VelodyneOptions& fov, int azimuth) {
  const auto lo = static_cast<int>(std::lround(fov.fov_min_deg * 100));
  const auto hi = static_cast<int>(std::lround(fov.fov_max_deg * 100));
  return lo <= hi ? azimuth >= lo && azimuth <= hi : azimuth >= lo || azimuth <= hi;
}

/// Rotates p about z so that its azimuth moves by `units` (0.01 deg).
Vec3 turn(const Vec3& p, int units) {
  const double a = -units * 0.01 * kDeg;  // azimuth is clockwise, atan2(y, x) counter-clockwise
  return Vec3(std::cos(a) * p.x() - std::sin(a) * p.y(), std::sin(a) * p.x() + std::cos(a) * p.y(), p.z());
}

struct Reference {
  const char* folder;
  const char* bag;
  const char* pcd;
  const char* calibration;
  NebulaRules rules;
  double min_range, max_range;
  ReturnMode returns;
  VelodyneOptions fov;
};

/// The nebula scan compared with the reference, and this decoder's scan that holds it.
void check_reference(const Reference& ref, std::size_t expected_points, std::size_t* direct_out = nullptr,
                     std::vector<NebulaReturn>* matched = nullptr) {
  const std::string dir = kVelodyne + "/nebula/" + ref.folder;
  const Recording rec = test::read_bag(dir + "/" + ref.bag);
  const test::Pcd pcd = test::read_binary_pcd(dir + "/" + ref.pcd);
  ASSERT_EQ(pcd.points, expected_points);
  const VelodyneCalibration cal = read_velodyne_calibration(kCalib + "/" + ref.calibration);

  // 1. nebula's scan, replayed: same points in the same order, coordinates within 1 mm.
  std::vector<NebulaReturn> every;
  const auto scans = nebula_scans(ref.rules, rec, cal, ref.min_range, ref.max_range, &every);
  const std::int64_t stamp = std::stoll(std::string(ref.pcd).substr(0, std::string(ref.pcd).find('.')));
  const NebulaScan* neb = nullptr;
  for (const NebulaScan& s : scans)
    if (rec.message_time_ns[static_cast<std::size_t>(rec.message[s.completing_packet])] == stamp) neb = &s;
  ASSERT_NE(neb, nullptr) << "no scan completes in the message of " << ref.pcd;
  ASSERT_EQ(neb->points.size(), pcd.points);
  std::size_t direct = 0, far = 0;
  double worst = 0.0, apart = 0.0;  // apart: our point against the reference, azimuths as decoded
  for (std::size_t i = 0; i < pcd.points; ++i) {
    const NebulaReturn& n = neb->points[i];
    const Vec3 expected = turn(n.r.xyz, n.azimuth - n.r.azimuth);
    const double d = (expected - pcd.xyz(i)).norm();
    worst = std::max(worst, d);
    apart = std::max(apart, (n.r.xyz - pcd.xyz(i)).norm());
    if (d > 1e-3) ++far;
    if (n.azimuth == n.r.azimuth) {
      ++direct;
      EXPECT_LT((n.r.xyz - pcd.xyz(i)).norm(), 1e-3) << i;  // same azimuth: our point itself
    }
  }
  EXPECT_EQ(far, 0u) << "worst " << worst << " m";
  if (direct_out) *direct_out = direct;
  if (matched) *matched = neb->points;

  // 2. This decoder's own scan (ScannerOptions / VelodyneOptions as a user sets them) holds the
  // same returns except at the two ends, where nebula cuts per packet and we per firing group,
  // and the blocks nebula's 359-degree rule drops whole.
  DriverOptions o;
  o.calibration = kCalib + "/" + ref.calibration;
  o.scan.returns = ref.returns;
  o.scan.cut_azimuth_deg = ref.rules.phase_deg;
  o.scan.min_range = ref.min_range;
  o.scan.max_range = ref.max_range;
  auto scanner = make_velodyne_scanner(o, rec.first(100), ref.fov);
  EXPECT_EQ(scanner->sensor().preset, velodyne_model_name(ref.rules.model)) << scanner->describe();
  std::vector<Scan> ours;
  for (std::size_t i = 0; i < rec.size(); ++i) scanner->add(rec.packet(i), ours);
  scanner->finish(ours);
  // 600 rpm; 151 (VLP-16 dual, VLP-32C) or 603-604 (VLS-128) packets per turn of 12 or 3 firings
  // (the sensors README): ~1810 firings per turn, 1792 columns.
  const SensorConfig sensor = scanner->sensor();
  EXPECT_NEAR(sensor.scan_rate_hz, 10.0, 0.1);
  EXPECT_EQ(sensor.Horizon_SCAN, 1792);
  EXPECT_EQ(sensor.N_scan, cal.size());
  EXPECT_NEAR(sensor.min_range, ref.min_range, 1e-12);
  using Key = std::tuple<double, double, double>;
  auto key = [](const Vec3& p) { return Key(p.x(), p.y(), p.z()); };
  std::map<Key, const NebulaReturn*> source;
  for (const NebulaReturn& n : every) source[key(n.r.xyz)] = &n;
  std::set<Key> in_nebula;
  for (const NebulaReturn& n : neb->points) in_nebula.insert(key(n.r.xyz));
  const Scan* best = nullptr;
  std::size_t best_common = 0;
  for (const Scan& s : ours) {
    std::size_t common = 0;
    for (const Vec3& p : s.xyz) common += in_nebula.count(key(p));
    if (common > best_common) {
      best_common = common;
      best = &s;
    }
  }
  ASSERT_NE(best, nullptr);
  EXPECT_TRUE(best->complete);
  const std::size_t head = neb->points.front().packet, tail = neb->completing_packet;
  std::size_t ours_only = 0, nebula_only = 0, by_359 = 0, by_edge = 0;
  std::set<Key> in_ours;
  for (const Vec3& p : best->xyz) {
    in_ours.insert(key(p));
    if (in_nebula.count(key(p))) continue;
    ++ours_only;
    ASSERT_TRUE(source.count(key(p))) << "a point no packet gives";
    const NebulaReturn& n = *source[key(p)];
    const bool rule_359 = ref.rules.cloud_0_359 && (n.block_azimuth > 35900 || n.azimuth > 35900);
    by_359 += rule_359;
    EXPECT_TRUE(rule_359 || n.packet == head || n.packet == tail || n.packet + 1 == head)
        << "packet " << n.packet << " block " << int(n.r.block);
  }
  for (const NebulaReturn& n : neb->points)
    if (!in_ours.count(key(n.r.xyz))) {
      ++nebula_only;
      // Our field of view sees our azimuth, nebula's its own: a point between the two may be
      // inside one and outside the other.
      const bool edge = !fov_contains(ref.fov, n.r.azimuth) && std::abs(n.azimuth - n.r.azimuth) < 1000;
      by_edge += edge;
      EXPECT_TRUE(edge || n.packet == head || n.packet == tail)
          << "packet " << n.packet << " block " << int(n.r.block);
    }
  std::cout << scanner->describe() << "\n";
  std::cout << ref.folder << ": replayed nebula scan within " << worst
            << " m of the PCD; our points (own azimuth) up to " << apart << " m from it\n";
  std::cout << ref.folder << ": nebula " << neb->points.size() << " points, " << direct
            << " at our azimuth; our scan " << best->size() << " points: " << best_common << " common, "
            << ours_only << " only ours (" << by_359
            << " by nebula's 359-degree rule, the rest in its end packets), " << nebula_only
            << " only nebula's (" << by_edge
            << " outside our field of view at our azimuth, the rest in its end packets " << head << ", "
            << tail << ")\n";
  EXPECT_GT(best_common, pcd.points * 95 / 100);
}

}  // namespace

TEST(Velodyne, NebulaVlp16DualReference) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  // nebula: VLP16, "Dual", scan_phase 0, VLP16.yaml, 0.3-300 m, cloud angles 0-359.
  VelodyneOptions fov;
  fov.fov_min_deg = 0.0;
  fov.fov_max_deg = 359.0;
  const Reference ref{"vlp16",
                      "1673400471837873222",
                      "1673400472138016708.pcd",
                      "VLP16.yaml",
                      {VelodyneModel::kVLP16, 0.0, true, false, true},
                      0.3,
                      300.0,
                      ReturnMode::kAll,
                      fov};
  std::size_t direct = 0;
  std::vector<NebulaReturn> points;
  check_reference(ref, 14831, &direct, &points);
  // nebula gives an odd block the next pair's azimuth and does not interpolate block 10: the
  // other points sit at our own azimuth.
  EXPECT_GT(direct, points.size() * 3 / 4);
  // The PCD's other fields, point by point.
  const test::Pcd pcd = test::read_binary_pcd(kVelodyne + "/nebula/vlp16/" + ref.pcd);
  const Recording rec = test::read_bag(kVelodyne + "/nebula/vlp16/" + ref.bag);
  const auto& channel = pcd.column("channel");
  const auto& intensity = pcd.column("intensity");
  const auto& distance = pcd.column("distance");
  const auto& azimuth = pcd.column("azimuth");
  const auto& elevation = pcd.column("elevation");
  const auto& time_stamp = pcd.column("time_stamp");
  const auto& return_type = pcd.column("return_type");
  std::map<std::tuple<std::size_t, int, int>, int> returns_of_firing;  // (packet, pair, channel)
  for (const NebulaReturn& n : points) ++returns_of_firing[{n.packet, n.r.block / 2, n.r.channel}];
  const VelodyneCalibration cal = read_velodyne_calibration(kCalib + "/VLP16.yaml");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const VelodyneReturn& r = points[i].r;
    ASSERT_EQ(channel[i], r.ring) << i;
    ASSERT_EQ(intensity[i], r.reflectivity) << i;
    ASSERT_NEAR(distance[i], r.range, 1e-6) << i;
    ASSERT_NEAR(azimuth[i], points[i].azimuth * 0.01 * kDeg, 1e-6) << i;
    ASSERT_NEAR(elevation[i], std::sin(cal.lasers[r.laser].vert_correction), 1e-6) << i;  // sin, not an angle
    // nebula times dual packets with the single-return table: 55.296 us * (2 * block + firing),
    // ours with the dual one, 55.296 us * (2 * (block / 2) + firing). The packet time is whole
    // seconds in nebula's test, so only the offset in the packet remains.
    const double toh_s = velodyne_packet_header(rec.packet(points[i].packet)).toh_us * 1e-6;
    const double ours_ns = (r.time - toh_s) * 1e9;  // decoded with the hour starting at 0
    const double shift_ns = 55296.0 * (r.block + r.block % 2);
    // Points moved on from the previous scan are re-stamped through the absolute packet time
    // (about 1.7e9 s in a double: 240 ns steps).
    ASSERT_NEAR(time_stamp[i], ours_ns + shift_ns, points[i].packet == points.front().packet ? 250.0 : 1.5)
        << i;
    const bool sole = returns_of_firing[{points[i].packet, r.block / 2, r.channel}] == 1;
    ASSERT_EQ(return_type[i] == 6, sole) << i << " return_type " << return_type[i];  // 6 = IDENTICAL
  }
}

TEST(Velodyne, NebulaVlp32Reference) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  // nebula: VLP32, SingleStrongest, scan_phase 180, VLP32.yaml, 0.4-50 m, cloud angles 270 -> 90.
  // The sensor sends only 270 -> 90 deg; the per-laser azimuth offsets (up to 4.2 deg) widen it.
  VelodyneOptions fov;
  fov.fov_min_deg = 265.0;
  fov.fov_max_deg = 95.0;
  const Reference ref{"vlp32",
                      "1713492677464078412",
                      "1713492677464078412.pcd",
                      "VLP32.yaml",
                      {VelodyneModel::kVLP32C, 180.0, false, true, false},
                      0.4,
                      50.0,
                      ReturnMode::kStrongest,
                      fov};
  std::size_t direct = 0;
  std::vector<NebulaReturn> points;
  // nebula interpolates channel j by j * 2.304 us, although the VLP-32C fires its lasers in pairs
  // (j / 2 * 2.304 us), and not at all in block 11: only points where both agree (after the
  // 0.01 deg rounding) sit at our azimuth.
  check_reference(ref, 26216, &direct, &points);
  EXPECT_GT(direct, 0u);
}

TEST(Velodyne, NebulaVls128Reference) {
  if (!have_sensors()) GTEST_SKIP() << "no " << kSensors;
  // nebula: VLS128, "Dual" (read as strongest from the packets), scan_phase 0, VLS128.yaml,
  // 0.3-300 m, cloud angles 0-359. Its distance unit is 4 mm whatever the YAML says (0.007).
  VelodyneOptions fov;
  fov.fov_min_deg = 0.0;
  fov.fov_max_deg = 359.0;
  const Reference ref{"vls128",
                      "1614315746471294674",
                      "1585897255376374245.pcd",
                      "VLS128.yaml",
                      {VelodyneModel::kVLS128, 0.0, true, false, true},
                      0.3,
                      300.0,
                      ReturnMode::kStrongest,
                      fov};
  std::size_t direct = 0;
  std::vector<NebulaReturn> points;
  // nebula interpolates the azimuth only in blocks 3 and 7 (the step to the next block is 0
  // inside a group of four), so the other blocks' points are turned back by up to one group step.
  check_reference(ref, 208680, &direct, &points);
  std::size_t interpolated = 0;
  for (const NebulaReturn& n : points)
    interpolated += (n.r.block == 3 || n.r.block == 7) && n.azimuth == n.r.azimuth;
  EXPECT_GT(interpolated, 0u);
  EXPECT_GT(direct, 0u);
}
