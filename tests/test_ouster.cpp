// Ouster decoder: metadata JSON (both layouts, the reduced file, errors), packet layouts, frames
// (window, loss, stragglers, CRC, IMU), returns, times, the XYZ model by construction, and the
// real recordings: the ouster-sdk digests, frame counts and geometry sanity.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "dloam/core/sensor.hpp"
#include "dloam/io/kitti.hpp"
#include "ouster_test_util.hpp"

using namespace dloam;
using namespace dloam::drivers;
using namespace ouster_test;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

const std::string kSensors = DLOAM_SENSORS_DIR;
const std::string kOuster = kSensors + "/ouster";

#define SKIP_WITHOUT(path)                                                         \
  do {                                                                             \
    if (!fs::exists(path)) GTEST_SKIP() << "shared sensor data missing: " << path; \
  } while (0)

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A flat-layout metadata text for synthetic streams.
std::string synthetic_json(const std::string& profile, int beams, int columns = 1024, int fps = 10) {
  nlohmann::json j;
  std::vector<double> alt, az;
  for (int i = 0; i < beams; ++i) {
    alt.push_back(15.0 - 30.0 * i / (beams - 1));  // top beam first, as Ouster lists them
    az.push_back(i % 2 ? -1.5 : 2.5);
  }
  std::vector<int> shift;
  for (int i = 0; i < beams; ++i) shift.push_back(i % 4 * 3);
  j["beam_altitude_angles"] = alt;
  j["beam_azimuth_angles"] = az;
  j["lidar_mode"] = std::to_string(columns) + "x" + std::to_string(fps);
  j["prod_line"] = "OS-1-" + std::to_string(beams);
  j["prod_sn"] = "992210000957";
  j["initialization_id"] = 5431293;
  j["build_rev"] = "v2.3.0";
  j["lidar_origin_to_beam_origin_mm"] = 15.806;
  j["lidar_to_sensor_transform"] = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1};
  j["data_format"] = {{"columns_per_frame", columns}, {"columns_per_packet", 16},
                      {"pixels_per_column", beams},   {"column_window", {0, columns - 1}},
                      {"pixel_shift_by_row", shift},  {"udp_profile_lidar", profile},
                      {"udp_profile_imu", "LEGACY"}};
  j["udp_port_lidar"] = 7502;
  j["udp_port_imu"] = 7503;
  return j.dump();
}

OusterMetadata synthetic(const std::string& profile, int beams, int columns = 1024) {
  return parse_ouster_metadata(synthetic_json(profile, beams, columns), "synthetic.json");
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

/// Feeds all packets, returns every scan (finish included).
std::vector<Scan> decode(Scanner& s, const std::vector<Packet>& packets) {
  std::vector<Scan> scans;
  for (const auto& p : packets) s.add(p, scans);
  s.finish(scans);
  return scans;
}

/// Sets RANGE (and RANGE2 where present) of a pixel from mm values.
void put_range(const OusterPacketFormat& f, std::uint8_t* px, std::uint32_t mm, std::uint32_t mm2 = 0) {
  put_field(px, *f.field(OusterField::kRange), mm);
  if (f.field(OusterField::kRange2)) put_field(px, *f.field(OusterField::kRange2), mm2);
}

// ---------------------------------------------------------------------------------------------
// Metadata

TEST(OusterMetadata, ReadsTheFlatLayout) {
  const std::string path = kOuster + "/OS-2-128-U1_v2.3.0_1024x10.json";
  SKIP_WITHOUT(path);
  const OusterMetadata md = load_ouster_metadata(path);
  EXPECT_FALSE(md.nested_layout);
  EXPECT_EQ(md.prod_line, "OS-2-128");
  EXPECT_EQ(md.prod_sn, 992210000957ull);
  EXPECT_EQ(md.init_id, 5431293u);
  EXPECT_EQ(md.firmware, "v2.3.0");
  EXPECT_EQ(md.profile, OusterProfile::kSingle);
  EXPECT_EQ(md.pixels_per_column, 128);
  EXPECT_EQ(md.columns_per_frame, 1024);
  EXPECT_EQ(md.fps, 10.0);
  EXPECT_EQ(md.columns_per_packet, 16);
  EXPECT_EQ(md.window_columns(), 1024);
  ASSERT_EQ(md.pixel_shift_by_row.size(), 128u);
  EXPECT_EQ(md.pixel_shift_by_row[0], 12);
  EXPECT_DOUBLE_EQ(md.beam_altitude_deg[0], 10.76);
  EXPECT_DOUBLE_EQ(md.lidar_origin_to_beam_origin_mm, 13.762);
  EXPECT_DOUBLE_EQ(md.beam_to_lidar(0, 3), 13.762);
  EXPECT_DOUBLE_EQ(md.lidar_to_sensor(2, 3), 78.296);
  EXPECT_DOUBLE_EQ(md.lidar_to_sensor(0, 0), -1.0);
  EXPECT_EQ(md.crc_expected(), 0);  // firmware 2.x writes no CRC
  EXPECT_EQ(md.udp_port_imu, 7503);
}

TEST(OusterMetadata, ReadsTheNestedLayout) {
  const std::string path = kOuster + "/bad/crc_test.json";
  SKIP_WITHOUT(path);
  const OusterMetadata md = load_ouster_metadata(path);
  EXPECT_TRUE(md.nested_layout);
  EXPECT_EQ(md.prod_line, "OS-0-128");
  EXPECT_EQ(md.prod_sn, 122247000785ull);
  EXPECT_EQ(md.init_id, 11394290u);
  EXPECT_EQ(md.firmware, "v3.2.0");  // from image_rev: build_rev is a commit hash
  EXPECT_EQ(md.profile, OusterProfile::kLowDataRate);
  EXPECT_FALSE(md.fusa_header);
  EXPECT_EQ(md.columns_per_frame, 512);
  EXPECT_EQ(md.lidar_mode, "512x10");
  EXPECT_EQ(md.pixels_per_column, 128);
  EXPECT_DOUBLE_EQ(md.beam_to_lidar(0, 3), 27.116);
  EXPECT_DOUBLE_EQ(md.lidar_to_sensor(2, 3), 38.195);
  EXPECT_DOUBLE_EQ(md.min_range_threshold_m, 0.5);
  EXPECT_EQ(md.return_order, OusterReturnOrder::kStrongestToWeakest);
  EXPECT_EQ(md.crc_expected(), 1);
}

TEST(OusterMetadata, TheFusaProfileImpliesTheFusaHeader) {
  const std::string path = kOuster + "/OS-1-128_767798045_1024x10_20230712_120049.json";
  SKIP_WITHOUT(path);
  const OusterMetadata md = load_ouster_metadata(path);
  EXPECT_EQ(md.profile, OusterProfile::kFusaLowDataRateDual);
  EXPECT_TRUE(md.fusa_header);
  EXPECT_EQ(md.crc_expected(), 0);
  EXPECT_EQ(md.init_id, 390076u);
}

TEST(OusterMetadata, TheReducedFileGetsTheSdkDefaults) {
  const std::string path = kOuster + "/OS-1-64_sensor_config_reduced.json";
  SKIP_WITHOUT(path);
  const OusterMetadata md = load_ouster_metadata(path);
  EXPECT_EQ(md.profile, OusterProfile::kLegacy);
  EXPECT_EQ(md.pixels_per_column, 64);
  EXPECT_EQ(md.columns_per_packet, 16);
  EXPECT_EQ(md.columns_per_frame, 1024);
  EXPECT_EQ(md.column_window_first, 0);
  EXPECT_EQ(md.column_window_last, 1023);
  EXPECT_TRUE(md.prod_line.empty());
  EXPECT_EQ(md.prod_sn, 0u);
  // ouster-sdk's default stagger for 1024 columns: 18, 12, 6, 0 repeated.
  ASSERT_EQ(md.pixel_shift_by_row.size(), 64u);
  for (int r = 0; r < 64; ++r)
    EXPECT_EQ(md.pixel_shift_by_row[static_cast<std::size_t>(r)], 6 * (3 - r % 4)) << r;
  EXPECT_DOUBLE_EQ(md.lidar_origin_to_beam_origin_mm, 12.163);  // first-generation default
  EXPECT_DOUBLE_EQ(md.lidar_to_sensor(2, 3), 36.18);
  EXPECT_DOUBLE_EQ(md.lidar_to_sensor(1, 1), -1.0);
}

TEST(OusterMetadata, NoProfileMeansLegacy) {
  const std::string path = kOuster + "/OS-1-32-G_v2.1.1_1024x10.json";
  SKIP_WITHOUT(path);
  const OusterMetadata md = load_ouster_metadata(path);
  EXPECT_EQ(md.profile, OusterProfile::kLegacy);
  EXPECT_EQ(md.pixels_per_column, 32);
  EXPECT_EQ(md.firmware_major, 2);
}

TEST(OusterMetadata, ErrorsNameTheFileAndTheKey) {
  auto with = [](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(synthetic_json("LEGACY", 16));
    edit(j);
    return error_of([&] { parse_ouster_metadata(j.dump(), "cfg/os1.json"); });
  };
  std::string e = with([](nlohmann::json& j) { j.erase("beam_altitude_angles"); });
  EXPECT_THAT(e, HasSubstr("cfg/os1.json"));
  EXPECT_THAT(e, HasSubstr("beam_altitude_angles"));
  EXPECT_THAT(e, HasSubstr("missing"));

  e = with([](nlohmann::json& j) { j["beam_azimuth_angles"][3] = "x"; });
  EXPECT_THAT(e, HasSubstr("beam_azimuth_angles[3]"));
  EXPECT_THAT(e, HasSubstr("expected a number"));

  e = with([](nlohmann::json& j) { j["beam_azimuth_angles"].erase(0); });
  EXPECT_THAT(e, HasSubstr("beam_azimuth_angles: has 15 entries"));

  e = with([](nlohmann::json& j) {
    j.erase("lidar_mode");
    j["data_format"].erase("columns_per_frame");
  });
  EXPECT_THAT(e, HasSubstr("lidar_mode: missing"));

  e = with([](nlohmann::json& j) { j["lidar_mode"] = 1024; });
  EXPECT_THAT(e, HasSubstr("lidar_mode: expected a string, got a number"));

  e = with([](nlohmann::json& j) { j["lidar_mode"] = "1024-10"; });
  EXPECT_THAT(e, HasSubstr("expected COLUMNSxRATE"));

  e = with([](nlohmann::json& j) { j["data_format"]["columns_per_frame"] = 2048; });
  EXPECT_THAT(e, HasSubstr("data_format.columns_per_frame: 2048 contradicts lidar_mode 1024x10"));

  e = with([](nlohmann::json& j) { j["data_format"]["pixel_shift_by_row"].erase(0); });
  EXPECT_THAT(e, HasSubstr("data_format.pixel_shift_by_row: has 15 entries for 16 beams"));

  e = with([](nlohmann::json& j) { j["data_format"]["pixels_per_column"] = 32; });
  EXPECT_THAT(e, HasSubstr("data_format.pixels_per_column: 32 pixels but 16 beam angles"));

  e = with([](nlohmann::json& j) { j["data_format"]["udp_profile_lidar"] = "RNG99"; });
  EXPECT_THAT(e, HasSubstr("unsupported lidar profile \"RNG99\""));

  e = with([](nlohmann::json& j) { j["data_format"]["column_window"] = {0, 5000}; });
  EXPECT_THAT(e, HasSubstr("data_format.column_window"));

  e = with([](nlohmann::json& j) { j["prod_line"] = "OS-1-64"; });
  EXPECT_THAT(e, HasSubstr("has 16 beams but prod_line is OS-1-64"));

  e = with([](nlohmann::json& j) { j["lidar_to_sensor_transform"][0] = 2; });
  EXPECT_THAT(e, HasSubstr("lidar_to_sensor_transform: the upper-left 3x3 block is not a rotation"));

  e = with([](nlohmann::json& j) { j["lidar_to_sensor_transform"].erase(15); });
  EXPECT_THAT(e, HasSubstr("lidar_to_sensor_transform: expected 16 numbers"));

  e = with([](nlohmann::json& j) { j["data_format"] = 3; });
  EXPECT_THAT(e, HasSubstr("data_format: expected a JSON object"));

  e = with([](nlohmann::json& j) { j["prod_sn"] = "12ab"; });
  EXPECT_THAT(e, HasSubstr("prod_sn: expected a decimal serial number"));

  // Nested layout: the key path is named.
  e = error_of([] {
    parse_ouster_metadata(
        R"({"sensor_info": {"prod_line": "OS-1-16"}, "beam_intrinsics": {"beam_altitude_angles": [1, 2]},
                             "config_params": {"lidar_mode": "1024x10"}})",
        "nested.json");
  });
  EXPECT_THAT(e, HasSubstr("nested.json: beam_intrinsics.beam_azimuth_angles: missing"));

  EXPECT_THAT(error_of([] { parse_ouster_metadata("{\"beam_altitude_angles\": [1, 2", "trunc.json"); }),
              HasSubstr("trunc.json: not valid JSON"));
  EXPECT_THAT(error_of([] { parse_ouster_metadata("[1, 2]", "array.json"); }),
              HasSubstr("array.json: expected a JSON object"));
  EXPECT_THAT(error_of([] { parse_ouster_metadata("{\"x\": 1}", "other.json"); }),
              HasSubstr("other.json: beam_altitude_angles: missing"));
  EXPECT_THAT(error_of([] { load_ouster_metadata("/nonexistent/os.json"); }),
              HasSubstr("/nonexistent/os.json: cannot open"));
}

// ---------------------------------------------------------------------------------------------
// Packet layouts

TEST(OusterProfiles, PacketSizesOfTheRecordings) {
  auto size = [](const char* profile, int beams) {
    return OusterPacketFormat(synthetic(profile, beams)).packet_size;
  };
  EXPECT_EQ(size("LEGACY", 32), 6464u);
  EXPECT_EQ(size("LEGACY", 64), 12608u);
  EXPECT_EQ(size("RNG19_RFL8_SIG16_NIR16_DUAL", 32), 8448u);
  EXPECT_EQ(size("RNG15_RFL8_NIR8", 128), 8448u);
  EXPECT_EQ(size("RNG19_RFL8_SIG16_NIR16", 128), 24832u);
  EXPECT_EQ(size("FUSA_RNG15_RFL8_NIR8_DUAL", 128), 16640u);
  EXPECT_EQ(size("RNG19_RFL8_SIG16_NIR16_DUAL", 128), 33024u);
}

TEST(OusterProfiles, FieldBitsMaskAndUpshift) {
  const OusterPacketFormat lb(synthetic("RNG15_RFL8_NIR8", 16));
  std::uint8_t px[4] = {0xFF, 0xFF, 0x34, 0xAB};  // range 0x7FFF, flag 1, reflectivity 0x34, nir 0xAB
  EXPECT_EQ(lb.field(OusterField::kRange)->decode(px), 0x7FFFu << 3);  // 8 mm units -> mm
  EXPECT_EQ(lb.field(OusterField::kFlags)->decode(px), 1u);
  EXPECT_EQ(lb.field(OusterField::kReflectivity)->decode(px), 0x34u);
  EXPECT_EQ(lb.field(OusterField::kNearIr)->decode(px), 0xABu << 4);
  EXPECT_EQ(lb.field(OusterField::kRange)->value_bytes(), 4);
  EXPECT_EQ(lb.field(OusterField::kNearIr)->value_bytes(), 2);
  EXPECT_EQ(lb.field(OusterField::kFlags)->value_bytes(), 1);
  EXPECT_EQ(lb.field(OusterField::kRange2), nullptr);

  const OusterPacketFormat single(synthetic("RNG19_RFL8_SIG16_NIR16", 16));
  std::uint8_t q[12] = {0xFF, 0xFF, 0xFF, 0xFF, 0x12, 0, 0x34, 0x56, 0x78, 0x9A, 0, 0};
  EXPECT_EQ(single.field(OusterField::kRange)->decode(q), 0x7FFFFu);  // 19 bits
  EXPECT_EQ(single.field(OusterField::kFlags)->decode(q), 0x1Fu);
  EXPECT_EQ(single.field(OusterField::kReflectivity)->decode(q), 0x12u);  // byte 4, not 3
  EXPECT_EQ(single.field(OusterField::kSignal)->decode(q), 0x5634u);
  EXPECT_EQ(single.field(OusterField::kNearIr)->decode(q), 0x9A78u);

  const OusterPacketFormat legacy(synthetic("LEGACY", 16));
  EXPECT_EQ(legacy.field(OusterField::kRange)->decode(q), 0xFFFFFu);  // 20 bits
  EXPECT_EQ(legacy.field(OusterField::kFlags)->decode(q), 0xFu);      // bits 28-31
  EXPECT_TRUE(legacy.legacy);
  EXPECT_EQ(legacy.column_size, 16u + 16u * 12u + 4u);
}

TEST(OusterProfiles, LooksLikeOuster) {
  for (const char* profile : {"LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG19_RFL8_SIG16_NIR16_DUAL",
                              "RNG15_RFL8_NIR8", "FUSA_RNG15_RFL8_NIR8_DUAL"}) {
    const PacketBuilder b(synthetic(profile, 64));
    const auto buf = b.packet(7, 512, nullptr);
    Packet p;
    p.data = buf.data();
    p.size = buf.size();
    EXPECT_TRUE(looks_like_ouster(p)) << profile;
    auto bad = buf;
    bad[b.fmt.packet_header_size + b.fmt.column_size + 8] ^= 0x01;  // column 1 measurement id
    p.data = bad.data();
    EXPECT_FALSE(looks_like_ouster(p)) << profile;
    p.data = buf.data();
    p.size = buf.size() - 1;
    EXPECT_FALSE(looks_like_ouster(p)) << profile;
  }
  std::vector<std::uint8_t> velodyne(1206, 0);
  velodyne[0] = 0xFF;
  velodyne[1] = 0xEE;
  Packet v;
  v.data = velodyne.data();
  v.size = velodyne.size();
  EXPECT_FALSE(looks_like_ouster(v));
}

// ---------------------------------------------------------------------------------------------
// Geometry by construction

/// The lidar-range-to-XYZ equations of the sensor documentation, written out per point:
/// x = (r - n) cos(th_e + th_a) cos(phi) + n cos(th_e), y likewise with sin, z = (r - n) sin(phi),
/// then the lidar_to_sensor transform; mm in, m out.
Vec3 documented_point(const OusterMetadata& md, int row, int m, double r_mm) {
  const double n = md.lidar_origin_to_beam_origin_mm;
  const double th_e = 2.0 * M_PI * (1.0 - static_cast<double>(m) / md.columns_per_frame);
  const double th_a = -md.beam_azimuth_deg[static_cast<std::size_t>(row)] * M_PI / 180.0;
  const double phi = md.beam_altitude_deg[static_cast<std::size_t>(row)] * M_PI / 180.0;
  const Eigen::Vector4d p((r_mm - n) * std::cos(th_e + th_a) * std::cos(phi) + n * std::cos(th_e),
                          (r_mm - n) * std::sin(th_e + th_a) * std::cos(phi) + n * std::sin(th_e),
                          (r_mm - n) * std::sin(phi), 1.0);
  return (md.lidar_to_sensor * p).head<3>() * 1e-3;
}

TEST(OusterGeometry, PointsFollowTheDocumentedModel) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16", 32);
  const OusterXyzLut lut(md);
  for (int m : {0, 1, 255, 256, 511, 777, 1023})
    for (int row : {0, 5, 17, 31})
      for (double r : {600.0, 5321.0, 87654.0}) {
        const Vec3 a = lut.point(row, m, r), b = documented_point(md, row, m, r);
        EXPECT_LT((a - b).norm(), 1e-9) << m << " " << row << " " << r;
      }
  // The 180 deg between the lidar frame (x at encoder 0, the connector) and the sensor frame:
  // measurement 0 looks backwards, W/4 to the left, W/2 forward: a clockwise spin seen from above.
  OusterMetadata flat = md;
  flat.beam_azimuth_deg.assign(32, 0.0);
  flat.beam_altitude_deg.assign(32, 0.0);
  flat.lidar_origin_to_beam_origin_mm = 0.0;
  flat.beam_to_lidar = Eigen::Matrix4d::Identity();
  const OusterXyzLut l2(flat);
  const double z0 = 0.03618;
  EXPECT_LT((l2.point(0, 0, 10000.0) - Vec3(-10.0, 0.0, z0)).norm(), 1e-9);
  EXPECT_LT((l2.point(0, 256, 10000.0) - Vec3(0.0, 10.0, z0)).norm(), 1e-9);
  EXPECT_LT((l2.point(0, 512, 10000.0) - Vec3(10.0, 0.0, z0)).norm(), 1e-9);
  EXPECT_LT((l2.point(0, 768, 10000.0) - Vec3(0.0, -10.0, z0)).norm(), 1e-9);
  EXPECT_NEAR(lut.beam_origin_height(), z0, 1e-12);
}

TEST(OusterGeometry, AFlatWallSeenByAllBeamsGivesAPlane) {
  for (const char* profile : {"LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG15_RFL8_NIR8"}) {
    const OusterMetadata md = synthetic(profile, 64);
    const PacketBuilder b(md);
    // The wall x = 6 m in the sensor frame: the range of each pixel from the documented model,
    // which is affine in r (p(r) = p(0) + r (p(1) - p(0))).
    auto range_to_wall = [&](int row, int m) -> std::uint32_t {
      const Vec3 p0 = documented_point(md, row, m, 0.0), p1 = documented_point(md, row, m, 1000.0);
      const double dx = (p1 - p0).x();
      if (dx < 0.3) return 0;  // looks away from the wall
      return static_cast<std::uint32_t>(std::lround((6.0 - p0.x()) / dx * 1000.0));
    };
    const auto bufs = b.frame(3, [&](int m, int row, std::uint8_t* px) {
      put_range(b.fmt, px, range_to_wall(row, m));
      put_field(px, *b.fmt.field(OusterField::kReflectivity), 100);
    });
    OusterScanner sc(md, DriverOptions{});
    const auto scans = decode(sc, packets_of(bufs, "wall"));
    ASSERT_EQ(scans.size(), 1u) << profile;
    const Scan& s = scans[0];
    EXPECT_TRUE(s.complete);
    ASSERT_GT(s.size(), 1000u);
    // Least-squares plane through the points.
    Eigen::MatrixXd A(static_cast<Eigen::Index>(s.size()), 3);
    for (std::size_t i = 0; i < s.size(); ++i) A.row(static_cast<Eigen::Index>(i)) = s.xyz[i].transpose();
    const Eigen::Vector3d c = A.colwise().mean();
    const Eigen::MatrixXd C = A.rowwise() - c.transpose();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(C, Eigen::ComputeThinV);
    const Eigen::Vector3d normal = svd.matrixV().col(2);
    EXPECT_GT(std::abs(normal.x()), 1.0 - 1e-5) << profile;
    EXPECT_NEAR(c.x(), 6.0, 0.005) << profile;
    double worst = 0.0;
    for (const auto& p : s.xyz) worst = std::max(worst, std::abs(p.x() - 6.0));
    // Range quantisation: rounded to 1 mm, or truncated to 8 mm units for RNG15.
    EXPECT_LT(worst, std::string(profile) == "RNG15_RFL8_NIR8" ? 0.0081 : 0.0006) << profile;
    // All beams see it, and ring 0 is the lowest beam.
    std::map<int, double> z_of_ring;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec3& p = s.xyz[i];
      if (std::abs(p.y()) < 0.2) z_of_ring[s.ring[i]] = p.z();
    }
    EXPECT_EQ(z_of_ring.size(), 64u) << profile;
    for (auto it = std::next(z_of_ring.begin()); it != z_of_ring.end(); ++it)
      EXPECT_GT(it->second, std::prev(it)->second) << profile << " ring " << it->first;
  }
}

TEST(OusterGeometry, DestaggeringAlignsAColumnOfTheRangeImage) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16", 16);
  const PacketBuilder b(md);
  // A measurement m of row r sees the scene at image column (m + shift[r]) mod W: put the range
  // of that column there, then destaggering must give constant columns.
  const auto bufs = b.frame(1, [&](int m, int row, std::uint8_t* px) {
    const int col = (m + md.pixel_shift_by_row[static_cast<std::size_t>(row)]) % md.columns_per_frame;
    put_range(b.fmt, px, 1000u + static_cast<std::uint32_t>(col));
  });
  OusterScanner sc(md, DriverOptions{});
  sc.keep_frames(true);
  decode(sc, packets_of(bufs, "stagger"));
  auto frames = sc.take_frames();
  ASSERT_EQ(frames.size(), 1u);
  const auto staggered = frames[0].field(sc.format(), OusterField::kRange);
  const auto image = ouster_destagger(staggered, md.columns_per_frame, md.pixel_shift_by_row);
  int misaligned = 0, staggered_misaligned = 0;
  for (int row = 0; row < 16; ++row)
    for (int col = 0; col < md.columns_per_frame; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * md.columns_per_frame + col);
      if (image[i] != 1000u + static_cast<std::uint32_t>(col)) ++misaligned;
      if (staggered[i] != 1000u + static_cast<std::uint32_t>(col)) ++staggered_misaligned;
    }
  EXPECT_EQ(misaligned, 0);
  EXPECT_GT(staggered_misaligned, 1000);  // the shifts are not all 0
}

// ---------------------------------------------------------------------------------------------
// Frames, returns, times

TEST(OusterFrames, LossWindowStragglersAndTheFrameId) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16", 16);
  const PacketBuilder b(md);
  auto fill = [&](int, int, std::uint8_t* px) { put_range(b.fmt, px, 5000); };
  std::vector<std::vector<std::uint8_t>> bufs;
  for (auto& p : b.frame(10, fill)) bufs.push_back(p);  // complete
  auto f11 = b.frame(11, fill);
  f11.erase(f11.begin() + 20);  // one packet lost
  for (auto& p : f11) bufs.push_back(p);
  bufs.push_back(b.packet(11, 320, fill));  // frame 11's missing packet, late but before frame 12
  for (int k = 0; k < 3; ++k) bufs.push_back(b.frame(12, fill)[static_cast<std::size_t>(k)]);  // partial tail
  OusterScanner sc(md, DriverOptions{});
  const auto scans = decode(sc, packets_of(bufs, "loss"));
  // Frame 11 is still open when its late packet comes: it completes it.
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_TRUE(scans[0].complete);
  EXPECT_EQ(scans[0].size(), 1024u * 16u);
  EXPECT_EQ(scans[0].first_packet, 0u);
  EXPECT_EQ(scans[0].last_packet, 63u);
  EXPECT_TRUE(scans[1].complete);
  EXPECT_FALSE(scans[2].complete);
  EXPECT_EQ(scans[2].size(), 3u * 16u * 16u);

  // A lost packet never recovered, and a straggler of an already finished frame.
  std::vector<std::vector<std::uint8_t>> b2;
  for (auto& p : f11) b2.push_back(p);  // frame 11 without packet 20
  for (auto& p : b.frame(12, fill)) b2.push_back(p);
  b2.push_back(b.packet(12, 0, fill));  // frame 12 is finished: dropped
  OusterScanner s2(md, DriverOptions{});
  const auto sc2 = decode(s2, packets_of(b2, "late"));
  ASSERT_EQ(sc2.size(), 2u);
  EXPECT_FALSE(sc2[0].complete);
  EXPECT_EQ(sc2[0].size(), 63u * 16u * 16u);
  EXPECT_TRUE(sc2[1].complete);
  EXPECT_EQ(s2.stats().late_packets, 1u);
  EXPECT_THAT(s2.describe(), HasSubstr("1 late packets dropped"));

  // Invalid columns: the frame is incomplete, their pixels give no points.
  std::vector<std::vector<std::uint8_t>> b3 = b.frame(13, fill);
  b3[5] = b.packet(13, 80, fill, /*valid=*/false);
  OusterScanner s3(md, DriverOptions{});
  const auto sc3 = decode(s3, packets_of(b3, "invalid"));
  ASSERT_EQ(sc3.size(), 1u);
  EXPECT_FALSE(sc3[0].complete);
  EXPECT_EQ(sc3[0].size(), 63u * 16u * 16u);
  EXPECT_EQ(s3.stats().invalid_columns, 16u);
}

TEST(OusterFrames, AColumnWindowFrameIsCompleteWithItsColumnsOnly) {
  nlohmann::json j = nlohmann::json::parse(synthetic_json("RNG15_RFL8_NIR8", 16));
  j["data_format"]["column_window"] = {896, 127};  // wraps through 0: 256 columns
  const OusterMetadata md = parse_ouster_metadata(j.dump(), "window.json");
  EXPECT_EQ(md.window_columns(), 256);
  const PacketBuilder b(md);
  const auto bufs = b.frame(4, [&](int, int, std::uint8_t* px) { put_range(b.fmt, px, 8000); });
  ASSERT_EQ(bufs.size(), 16u);
  OusterScanner sc(md, DriverOptions{});
  const auto scans = decode(sc, packets_of(bufs, "window"));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_TRUE(scans[0].complete);
  EXPECT_EQ(scans[0].size(), 256u * 16u);
  for (const auto& p : scans[0].xyz) EXPECT_LT(p.x(), 0.0);  // the window looks backwards
}

TEST(OusterFrames, DualReturns) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16_DUAL", 16);
  const PacketBuilder b(md);
  const OusterPacketFormat& f = b.fmt;
  // Per pixel: RANGE 20 m (strongest, reflectivity 50, signal 900), RANGE2 8 m (reflectivity 30,
  // signal 100); on row 0 only RANGE; on row 1 both the same.
  auto fill = [&](int, int row, std::uint8_t* px) {
    if (row == 0) {
      put_range(f, px, 20000, 0);
    } else if (row == 1) {
      put_range(f, px, 20000, 20000);
    } else {
      put_range(f, px, 20000, 8000);
    }
    put_field(px, *f.field(OusterField::kReflectivity), 50);
    put_field(px, *f.field(OusterField::kReflectivity2), 30);
    put_field(px, *f.field(OusterField::kSignal), 900);
    put_field(px, *f.field(OusterField::kSignal2), 100);
  };
  const auto bufs = b.frame(2, fill);
  auto run = [&](ReturnMode mode, const OusterMetadata& meta) {
    DriverOptions o;
    o.scan.returns = mode;
    OusterScanner sc(meta, o);
    auto scans = decode(sc, packets_of(bufs, "dual"));
    EXPECT_EQ(scans.size(), 1u);
    return scans.empty() ? Scan{} : scans[0];
  };
  auto count_range = [](const Scan& s, double near_m) {
    std::size_t n = 0;
    for (const auto& p : s.xyz)
      if (p.norm() < near_m) ++n;
    return n;
  };
  const std::size_t pixels = 1024u * 16u, cols = 1024u;
  const Scan strongest = run(ReturnMode::kStrongest, md);
  EXPECT_EQ(strongest.size(), pixels);
  EXPECT_EQ(count_range(strongest, 15.0), 0u);
  EXPECT_EQ(strongest.intensity[0], 50.0f);
  // Strongest is the farther return here: return_id 1 where a nearer one exists (rows 2-15).
  EXPECT_EQ(std::count(strongest.return_id.begin(), strongest.return_id.end(), 1),
            static_cast<long>(cols * 14));

  const Scan first = run(ReturnMode::kFirst, md);
  EXPECT_EQ(first.size(), pixels);
  EXPECT_EQ(count_range(first, 15.0), cols * 14);
  EXPECT_EQ(std::count(first.return_id.begin(), first.return_id.end(), 0), static_cast<long>(pixels));

  const Scan last = run(ReturnMode::kLast, md);
  EXPECT_EQ(count_range(last, 15.0), 0u);

  const Scan all = run(ReturnMode::kAll, md);
  EXPECT_EQ(all.size(), pixels + cols * 14);  // row 1's identical second return is not repeated
  EXPECT_EQ(count_range(all, 15.0), cols * 14);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all.xyz[i].norm() < 15.0) {
      EXPECT_EQ(all.return_id[i], 0);
      EXPECT_EQ(all.intensity[i], 30.0f);
    }

  // Under NEAREST_TO_FARTHEST the strongest is the return with the higher SIGNAL: RANGE here too.
  OusterMetadata nearest = md;
  nearest.return_order = OusterReturnOrder::kNearestToFarthest;
  EXPECT_EQ(count_range(run(ReturnMode::kStrongest, nearest), 15.0), 0u);
}

TEST(OusterFrames, TimesAreTheColumnTimestamps) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16", 16);
  PacketBuilder b(md);
  const auto bufs = b.frame(0, [&](int, int, std::uint8_t* px) { put_range(b.fmt, px, 5000); });
  // Internal oscillator: sensor time 1000 s, recording time 1.7e9 s. The first packet's last
  // column is put at that packet's recording time.
  const double rec0 = 1.7e9;
  OusterScanner sc(md, DriverOptions{});
  const auto scans = decode(sc, packets_of(bufs, "osc", rec0, 0.1 / 64));
  ASSERT_EQ(scans.size(), 1u);
  const Scan& s = scans[0];
  const double t15 = static_cast<double>(b.column_ns(0, 15)) * 1e-9;
  EXPECT_NEAR(s.start, rec0 - (t15 - static_cast<double>(b.column_ns(0, 0)) * 1e-9), 1e-6);
  EXPECT_NEAR(s.end - s.start, 0.1 * 1023.0 / 1024.0, 1e-6);
  EXPECT_EQ(s.stamps.front(), s.start);
  EXPECT_EQ(s.stamps.back(), s.end);
  for (std::size_t i = 1; i < s.stamps.size(); ++i) ASSERT_GE(s.stamps[i], s.stamps[i - 1]);
  EXPECT_THAT(sc.describe(), HasSubstr("sensor clock + recording offset"));

  // A synchronised sensor clock (PTP): its times are kept.
  b.t0_ns = 1'700'000'000'000'000'000ull;
  const auto synced = b.frame(0, [&](int, int, std::uint8_t* px) { put_range(b.fmt, px, 5000); });
  OusterScanner s2(md, DriverOptions{});
  const auto sc2 = decode(s2, packets_of(synced, "ptp", 1.7e9 + 0.003, 0.1 / 64));
  ASSERT_EQ(sc2.size(), 1u);
  EXPECT_NEAR(sc2[0].start, 1.7e9, 1e-6);
  EXPECT_THAT(s2.describe(), HasSubstr("times: sensor clock"));
}

TEST(OusterFrames, SensorModelFromTheMetadata) {
  const OusterMetadata md = synthetic("RNG19_RFL8_SIG16_NIR16", 32, 2048);
  OusterScanner sc(md, DriverOptions{});
  const SensorConfig s = sc.sensor();
  EXPECT_NO_THROW(s.validate());
  EXPECT_EQ(s.preset, "OS-1-32");
  EXPECT_EQ(s.N_scan, 32);
  EXPECT_EQ(s.Horizon_SCAN, 2048);
  EXPECT_EQ(s.scan_rate_hz, 10.0);
  ASSERT_EQ(s.beam_elevations_deg.size(), 32u);
  EXPECT_DOUBLE_EQ(s.beam_elevations_deg.front(), -15.0);  // bottom beam first
  EXPECT_DOUBLE_EQ(s.beam_elevations_deg.back(), 15.0);
  // Beam origin heights: every point of ring k, near or far, lies on the cone
  // z = offset_k + rho tan(elevation_k) (rho: distance from the sensor's z axis).
  ASSERT_EQ(s.beam_vertical_offsets_m.size(), 32u);
  const OusterXyzLut& lut = sc.lut();
  for (int row = 0; row < 32; ++row) {
    const int ring = 31 - row;  // the synthetic beams are listed top first, evenly spaced
    const double tan_el = std::tan(s.beam_elevations_deg[static_cast<std::size_t>(ring)] * M_PI / 180.0);
    for (int m : {0, 333, 1500})
      for (double r : {700.0, 3000.0, 60000.0}) {
        const Vec3 p = lut.point(row, m, r);
        EXPECT_NEAR(
            p.z(),
            s.beam_vertical_offsets_m[static_cast<std::size_t>(ring)] + std::hypot(p.x(), p.y()) * tan_el,
            2e-5)
            << row << " " << m << " " << r;
      }
  }
  // Without the beam origin offset n they would all be the mid-plane height.
  EXPECT_NEAR(
      s.beam_vertical_offsets_m[16],
      0.03618 - 0.015806 * std::cos(-1.5 * M_PI / 180.0) * std::tan(s.beam_elevations_deg[16] * M_PI / 180.0),
      1e-12);
  EXPECT_EQ(s.min_range, 0.5);
  EXPECT_EQ(s.max_range, 200.0);
  DriverOptions o;
  o.scan.min_range = 2.0;
  o.scan.max_range = 80.0;
  const SensorConfig s2 = OusterScanner(md, o).sensor();
  EXPECT_EQ(s2.min_range, 2.0);
  EXPECT_EQ(s2.max_range, 80.0);
  EXPECT_THAT(sc.describe(),
              HasSubstr("Ouster OS-1-32 (fw v2.3.0, sn 992210000957), RNG19_RFL8_SIG16_NIR16, 2048x10"));
  // The model name, when given, must be the metadata's.
  o.model = "OS-2-32";
  EXPECT_THAT(error_of([&] { OusterScanner(md, o); }),
              HasSubstr("synthetic.json: the metadata is for a OS-1-32"));
  o.model = "OS1-32";
  EXPECT_NO_THROW(OusterScanner(md, o));
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(OusterBadInput, PacketsThatDoNotFitTheMetadata) {
  const OusterMetadata md = synthetic("RNG15_RFL8_NIR8", 128);
  const PacketBuilder b(md);
  auto buf = b.packet(1, 0, nullptr);
  OusterScanner sc(md, DriverOptions{});
  std::vector<Scan> out;
  Packet p;
  p.data = buf.data();
  p.size = buf.size() - 1;  // truncated
  p.where = "cap.pcap: packet 17";
  std::string e = error_of([&] { sc.add(p, out); });
  EXPECT_THAT(e, HasSubstr("cap.pcap: packet 17: a 8447-byte packet does not fit synthetic.json"));
  EXPECT_THAT(
      e,
      HasSubstr("RNG15_RFL8_NIR8 with 128 pixels and 16 columns per packet makes 8448-byte lidar packets"));

  // The same size, another layout: 8448 B is also RNG19_RFL8_SIG16_NIR16_DUAL with 32 pixels.
  const PacketBuilder dual(synthetic("RNG19_RFL8_SIG16_NIR16_DUAL", 32));
  EXPECT_EQ(dual.fmt.packet_size, 8448u);

  // A LEGACY OS1-32 packet against an OS-0-128 metadata: named, with what the size would be.
  const PacketBuilder legacy32(synthetic("LEGACY", 32));
  auto lbuf = legacy32.packet(1, 0, nullptr);
  p.data = lbuf.data();
  p.size = lbuf.size();
  e = error_of([&] { sc.add(p, out); });
  EXPECT_THAT(e, HasSubstr("a 6464-byte packet does not fit"));
  EXPECT_THAT(e, HasSubstr("6464 B would be LEGACY with 32 pixels"));

  // Another sensor's serial number, another initialization id, a non-lidar packet type.
  PacketBuilder other(md);
  other.prod_sn = 122150000150ull;
  std::vector<std::uint8_t> obuf = other.packet(1, 0, nullptr);
  auto use = [&] {
    p.data = obuf.data();
    p.size = obuf.size();
  };
  use();
  EXPECT_THAT(
      error_of([&] { sc.add(p, out); }),
      HasSubstr(
          "packet 17: the packet comes from sensor 122150000150 but synthetic.json is the metadata of sensor "
          "992210000957"));
  other.prod_sn = md.prod_sn;
  other.init_id = 77;
  obuf = other.packet(1, 0, nullptr);
  use();
  EXPECT_THAT(error_of([&] { sc.add(p, out); }),
              HasSubstr("initialization id 77 differs from synthetic.json's 5431293"));
  obuf = b.packet(1, 0, nullptr);
  obuf[0] = 3;
  use();
  EXPECT_THAT(error_of([&] { sc.add(p, out); }), HasSubstr("packet type 3 is not a lidar packet"));

  // A measurement id beyond the metadata's columns per frame (a 2048-column stream, 1024 JSON).
  obuf = b.packet(1, 1024, nullptr);
  use();
  EXPECT_THAT(
      error_of([&] { sc.add(p, out); }),
      HasSubstr("packet 17: measurement_id 1024 in column 0 does not fit the 1024 columns per frame of "
                "synthetic.json"));

  // IMU packets are ignored and counted.
  std::vector<std::uint8_t> imu(48, 0);
  Packet ip;
  ip.data = imu.data();
  ip.size = imu.size();
  ip.port = 7503;
  OusterScanner s2(md, DriverOptions{});
  s2.add(ip, out);
  EXPECT_EQ(s2.stats().imu_packets, 1u);
  EXPECT_THAT(s2.describe(), HasSubstr("1 IMU packets ignored"));

  // The IMU profile of firmware 3: 32 B header, 100 B NMEA block, 36 B per sample, 32 B footer.
  nlohmann::json j = nlohmann::json::parse(synthetic_json("RNG15_RFL8_NIR8", 128));
  j["data_format"]["udp_profile_imu"] = "ACCEL32_GYRO32_NMEA";
  const OusterMetadata no_count = parse_ouster_metadata(j.dump(), "imu.json");
  EXPECT_EQ(no_count.imu_packet_size, 0);
  j["imu_data_format"] = {{"imu_measurements_per_packet", 8}};
  const OusterMetadata counted = parse_ouster_metadata(j.dump(), "imu.json");
  EXPECT_EQ(counted.imu_packet_size, 164 + 36 * 8);
  std::vector<std::uint8_t> imu3(164 + 36 * 8, 0);
  ip.data = imu3.data();
  ip.size = imu3.size();
  ip.port = 0;
  for (const OusterMetadata* m : {&no_count, &counted}) {
    OusterScanner s3(*m, DriverOptions{});
    s3.add(ip, out);
    EXPECT_EQ(s3.stats().imu_packets, 1u);
  }
  imu3.resize(48);  // not this profile's IMU packet
  ip.size = imu3.size();
  ip.data = imu3.data();
  EXPECT_THAT(error_of([&] { OusterScanner(counted, DriverOptions{}).add(ip, out); }),
              HasSubstr("a 48-byte packet does not fit imu.json"));
}

TEST(OusterBadInput, RandomBytesGiveInputErrorsOrScansNeverAnythingElse) {
  std::mt19937 rng(7);
  for (const char* profile :
       {"LEGACY", "RNG19_RFL8_SIG16_NIR16_DUAL", "RNG15_RFL8_NIR8", "FUSA_RNG15_RFL8_NIR8_DUAL"}) {
    const OusterMetadata md = synthetic(profile, 32);
    const PacketBuilder b(md);
    OusterScanner sc(md, DriverOptions{});
    std::vector<Scan> out;
    std::size_t errors = 0, taken = 0;
    for (int k = 0; k < 300; ++k) {
      // A valid packet with random pixels and a few random header bytes, or random sizes.
      std::vector<std::uint8_t> buf =
          b.packet(static_cast<std::uint32_t>(k / 8), (k % 8) * 16, [&](int, int, std::uint8_t* px) {
            for (std::size_t i = 0; i < b.fmt.pixel_size; ++i) px[i] = static_cast<std::uint8_t>(rng());
          });
      if (k % 3 == 0) buf[rng() % buf.size()] = static_cast<std::uint8_t>(rng());
      if (k % 7 == 0) buf.resize(rng() % (buf.size() + 64));
      Packet p;
      p.data = buf.data();
      p.size = buf.size();
      p.where = "random: packet " + std::to_string(k);
      try {
        sc.add(p, out);
        ++taken;
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("random: packet " + std::to_string(k))) << profile;
        ++errors;
      }
    }
    sc.finish(out);
    EXPECT_GT(taken, 100u) << profile;
    EXPECT_GT(errors, 10u) << profile;
    for (const auto& s : out)
      for (const auto& q : s.xyz) ASSERT_TRUE(q.allFinite()) << profile;
  }
}

TEST(OusterBadInput, MakeScannerNeedsTheMetadataAndChecksTheFirstPackets) {
  EXPECT_THAT(error_of([] { make_ouster_scanner(DriverOptions{}, {}); }),
              HasSubstr("cannot be decoded without the sensor's metadata JSON"));
  const std::string json = kOuster + "/OS-0-128-U1_v2.3.0_1024x10.json";
  const std::string pcap32 = kOuster + "/OS-1-32-G_v2.1.1_1024x10.pcap";
  SKIP_WITHOUT(json);
  SKIP_WITHOUT(pcap32);
  DriverOptions o;
  o.calibration = json;
  const auto recs = read_udp_pcap(pcap32);
  const auto pk = packets_of(recs, "OS-1-32-G_v2.1.1_1024x10.pcap");
  const std::string e = error_of([&] { make_ouster_scanner(o, pk); });
  EXPECT_THAT(e,
              HasSubstr("OS-1-32-G_v2.1.1_1024x10.pcap: packet 0: a 6464-byte packet does not fit " + json));
  EXPECT_THAT(e, HasSubstr("6464 B would be LEGACY with 32 pixels"));
}

TEST(OusterBadInput, ABadCrcIsCountedAndItsPacketDropped) {
  nlohmann::json j = nlohmann::json::parse(synthetic_json("RNG15_RFL8_NIR8", 16));
  j["build_rev"] = "v3.2.0";
  const OusterMetadata md = parse_ouster_metadata(j.dump(), "fw32.json");
  const PacketBuilder b(md);
  auto bufs = b.frame(9, [&](int, int, std::uint8_t* px) { put_range(b.fmt, px, 4000); });
  for (auto& p : bufs)
    put_le(p.data() + p.size() - 8, OusterPacketFormat::compute_crc(p.data(), p.size()), 8);
  bufs[7][100] ^= 0x40;  // corrupt one packet
  OusterScanner sc(md, DriverOptions{});
  const auto scans = decode(sc, packets_of(bufs, "crc"));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_FALSE(scans[0].complete);
  EXPECT_EQ(scans[0].size(), 63u * 16u * 16u);
  EXPECT_EQ(sc.stats().crc_checked, 64u);
  EXPECT_EQ(sc.stats().crc_bad, 1u);
  EXPECT_THAT(sc.describe(), HasSubstr("CRC: 63 good, 1 bad (dropped)"));
}

// ---------------------------------------------------------------------------------------------
// Recordings

struct Recording {
  OusterMetadata md;
  std::vector<UdpRecord> records;
  std::vector<Packet> packets;
};

Recording load(const std::string& pcap, const std::string& json) {
  Recording r;
  r.md = load_ouster_metadata(json);
  r.records = read_udp_pcap(pcap);
  r.packets = packets_of(r.records, fs::path(pcap).filename().string());
  return r;
}

/// ouster-sdk's StreamDigest of a recording from this decoder's packet layout and frames.
struct Digest {
  std::map<std::string, std::string> packet_hash;
  std::vector<std::map<std::string, std::string>> frames;
};

template <typename T>
void add_array(Md5& h, const std::vector<std::uint32_t>& v) {
  std::vector<T> a(v.begin(), v.end());
  h.update(a);
}

void hash_sized(Md5& h, const std::vector<std::uint32_t>& v, int bytes) {
  if (bytes == 1) {
    add_array<std::uint8_t>(h, v);
  } else if (bytes == 2) {
    add_array<std::uint16_t>(h, v);
  } else {
    add_array<std::uint32_t>(h, v);
  }
}

Digest digest_of(const Recording& rec) {
  OusterScanner sc(rec.md, DriverOptions{});
  sc.keep_frames(true);
  const OusterPacketFormat& f = sc.format();
  std::map<std::string, Md5> ph;
  const int H = f.pixels_per_column, C = f.columns_per_packet;
  std::vector<Scan> scans;
  for (const auto& p : rec.packets) {
    if (!sc.check(p)) continue;  // IMU
    std::vector<std::uint64_t> ts;
    std::vector<std::uint32_t> enc, status;
    std::vector<std::uint16_t> mid, fid;
    for (int c = 0; c < C; ++c) {
      const std::uint8_t* col = f.column(p.data, c);
      ts.push_back(f.col_timestamp(col));
      enc.push_back(f.col_encoder(col));
      mid.push_back(f.col_measurement_id(col));
      status.push_back(f.col_status(col));
      fid.push_back(f.col_frame_id(col));
    }
    ph["TIMESTAMP"].update(ts);
    ph["ENCODER_COUNT"].update(enc);
    ph["MEASUREMENT_ID"].update(mid);
    ph["STATUS"].update(status);
    ph["FRAME_ID"].update(fid);
    for (const auto& layout : f.fields()) {
      std::vector<std::uint32_t> img(static_cast<std::size_t>(H * C));
      for (int c = 0; c < C; ++c)
        for (int px = 0; px < H; ++px)
          img[static_cast<std::size_t>(px * C + c)] = layout.decode(f.pixel(f.column(p.data, c), px));
      hash_sized(ph[to_string(layout.field)], img, layout.value_bytes());
    }
    sc.add(p, scans);
  }
  sc.finish(scans);
  Digest d;
  for (auto& [k, h] : ph) d.packet_hash[k] = h.hex();
  for (const OusterFrame& fr : sc.take_frames()) {
    std::map<std::string, std::string> m;
    m["FRAME_ID"] = std::to_string(fr.frame_id);
    Md5 t, s, i;
    t.update(fr.timestamp);
    s.update(std::vector<std::uint64_t>(fr.status.begin(), fr.status.end()));
    i.update(fr.measurement_id);
    m["TIMESTAMP"] = t.hex();
    m["STATUS"] = s.hex();
    m["MEASUREMENT_ID"] = i.hex();
    for (const auto& layout : f.fields()) {
      Md5 h;
      hash_sized(h, fr.field(f, layout.field), layout.value_bytes());
      m[to_string(layout.field)] = h.hex();
    }
    d.frames.push_back(m);
  }
  return d;
}

class OusterDigest : public ::testing::TestWithParam<std::string> {};

TEST_P(OusterDigest, MatchesTheStoredSdkDigest) {
  const std::string base = kOuster + "/" + GetParam() + "_1024x10";
  SKIP_WITHOUT(base + ".pcap");
  const Recording rec = load(base + ".pcap", base + ".json");
  const Digest got = digest_of(rec);
  const nlohmann::json want = nlohmann::json::parse(read_text(base + "_digest.json"));
  ASSERT_TRUE(want.contains("packet_hash"));
  int compared = 0;
  for (const auto& [key, value] : want["packet_hash"].items()) {
    if (key == "ENCODER_COUNT") continue;  // ouster-sdk's check skips it too
    ASSERT_TRUE(got.packet_hash.count(key)) << "packet field " << key;
    EXPECT_EQ(got.packet_hash.at(key), value.get<std::string>()) << "packet_hash " << key;
    ++compared;
  }
  EXPECT_GE(compared, 9);
  const auto& frames = want.contains("frames") ? want["frames"] : want["scans"];
  ASSERT_EQ(got.frames.size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (const auto& [key, value] : frames[k].items()) {
      if (key == "ENCODER_COUNT") continue;
      ASSERT_TRUE(got.frames[k].count(key)) << "frame field " << key;
      EXPECT_EQ(got.frames[k].at(key), value.get<std::string>()) << "frame " << k << " " << key;
      ++compared;
    }
  EXPECT_GE(compared, 16);
}

INSTANTIATE_TEST_SUITE_P(Recordings, OusterDigest,
                         ::testing::Values("OS-2-32-U0_v2.0.0", "OS-1-32-G_v2.1.1", "OS-0-32-U1_v2.2.0",
                                           "OS-2-128-U1_v2.3.0", "OS-0-128-U1_v2.3.0"),
                         [](const auto& p) {
                           std::string n = p.param;
                           std::replace_if(
                               n.begin(), n.end(),
                               [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
                           return n;
                         });

std::vector<Scan> decode_recording(const std::string& pcap, const std::string& json,
                                   OusterStats* stats = nullptr, DriverOptions o = {}) {
  const auto recs = read_udp_pcap(pcap);
  const auto pk = packets_of(recs, fs::path(pcap).filename().string());
  o.calibration = json;
  auto sc = make_ouster_scanner(
      o, std::vector<Packet>(pk.begin(), pk.begin() + std::min<std::size_t>(pk.size(), 8)));
  auto scans = decode(*sc, pk);
  if (stats) *stats = dynamic_cast<OusterScanner&>(*sc).stats();
  return scans;
}

TEST(OusterRecordings, LooksLikeOusterTellsTheLidarPackets) {
  // Every lidar packet of every Ouster capture, none of its IMU packets, no Velodyne packet.
  std::size_t lidar = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kOuster)) {
    if (entry.path().extension() != ".pcap") continue;
    const auto recs = read_udp_pcap(entry.path().string());
    for (const auto& p : packets_of(recs, entry.path().filename().string())) {
      EXPECT_EQ(looks_like_ouster(p), p.port == 7502) << p.where << " (" << p.size << " B)";
      lidar += p.port == 7502 ? 1 : 0;
    }
  }
  EXPECT_EQ(lidar, 64u * 6 + 1 + 192 + 8 + 34);
  const std::string vlp = kSensors + "/velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap";
  if (fs::exists(vlp)) {
    const auto recs = read_udp_pcap(vlp);
    for (const auto& p : packets_of(recs, "vlp-16")) ASSERT_FALSE(looks_like_ouster(p)) << p.where;
  }
}

TEST(OusterRecordings, AnotherSensorsMetadataOfTheSameLayoutIsAnError) {
  // OS-1-128 packets with the OS-0-128's metadata: both RNG15_RFL8_NIR8 with 128 pixels (8448 B).
  const std::string pcap = kOuster + "/OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  const std::string json = kOuster + "/OS-0-128-U1_v2.3.0_1024x10.json";
  SKIP_WITHOUT(pcap);
  const auto recs = read_udp_pcap(pcap);
  const auto pk = packets_of(recs, "lb_n3.pcap");
  DriverOptions o;
  o.calibration = json;
  EXPECT_THAT(error_of([&] { make_ouster_scanner(o, pk); }),
              HasSubstr("lb_n3.pcap: packet 0: the packet comes from sensor 122201000998 but " + json +
                        " is the metadata of sensor 122150000150"));
}

TEST(OusterRecordings, LegacyFirmware2WithTheReducedJsonGivesOneFrame) {
  const std::string pcap = kOuster + "/OS-1-64_1024x10_fw20.pcap";
  SKIP_WITHOUT(pcap);
  OusterStats st;
  const auto scans = decode_recording(pcap, kOuster + "/OS-1-64_sensor_config_reduced.json", &st);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_TRUE(scans[0].complete);
  EXPECT_EQ(st.lidar_packets, 64u);
  EXPECT_EQ(st.imu_packets, 11u);
  std::set<int> rings(scans[0].ring.begin(), scans[0].ring.end());
  EXPECT_EQ(rings.size(), 64u);
}

TEST(OusterRecordings, FusaPartialFrame) {
  const std::string base = kOuster + "/OS-1-128_767798045_1024x10_20230712_120049";
  SKIP_WITHOUT(base + ".pcap");
  const Recording rec = load(base + ".pcap", base + ".json");
  OusterScanner sc(rec.md, DriverOptions{});
  sc.keep_frames(true);
  const auto scans = decode(sc, rec.packets);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_FALSE(scans[0].complete);
  EXPECT_EQ(sc.stats().imu_packets, 2u);
  EXPECT_EQ(sc.stats().crc_checked, 0u);  // the FuSa header carries no CRC
  auto frames = sc.take_frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].frame_id, 229u);
  EXPECT_EQ(frames[0].valid_columns, 128);
  auto nonzero = [](const std::vector<std::uint32_t>& v) {
    return std::count_if(v.begin(), v.end(), [](std::uint32_t x) { return x != 0; });
  };
  EXPECT_EQ(nonzero(frames[0].field(sc.format(), OusterField::kFlags)), 8);
  EXPECT_EQ(nonzero(frames[0].field(sc.format(), OusterField::kFlags2)), 0);
  EXPECT_GT(scans[0].size(), 0u);
}

TEST(OusterRecordings, CrcTestHas34GoodCrcsAndOneCompleteFrameOfTwo) {
  const std::string pcap = kOuster + "/bad/crc_test.pcap";
  SKIP_WITHOUT(pcap);
  OusterStats st;
  const auto scans = decode_recording(pcap, kOuster + "/bad/crc_test.json", &st);
  EXPECT_EQ(st.crc_checked, 34u);
  EXPECT_EQ(st.crc_bad, 0u);
  EXPECT_EQ(st.imu_packets, 10u);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_TRUE(scans[0].complete);
  EXPECT_FALSE(scans[1].complete);
  EXPECT_EQ(std::count_if(scans.begin(), scans.end(), [](const Scan& s) { return s.complete; }), 1);
}

TEST(OusterRecordings, EmptyPcapGivesNoFrames) {
  const std::string pcap = kOuster + "/bad/empty_pcap.pcap";
  SKIP_WITHOUT(pcap);
  OusterStats st;
  const auto scans = decode_recording(pcap, kOuster + "/bad/empty_pcap.json", &st);
  EXPECT_TRUE(scans.empty());
  EXPECT_EQ(st.lidar_packets, 0u);
}

TEST(OusterRecordings, ThreeFramesOfLbN3AndTheSinglePacketFile) {
  const std::string pcap = kOuster + "/OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  SKIP_WITHOUT(pcap);
  const auto scans = decode_recording(pcap, kOuster + "/OS-1-128_v2.3.0_1024x10.json");
  ASSERT_EQ(scans.size(), 3u);
  for (const auto& s : scans) {
    EXPECT_TRUE(s.complete);
    EXPECT_NEAR(s.end - s.start, 0.1 * 1023.0 / 1024.0, 1e-3);
  }
  EXPECT_NEAR(scans[1].start - scans[0].start, 0.1, 1e-3);

  const auto one = decode_recording(kOuster + "/OS-0-32-U1_v2.2.0_1024x10-single-packet.pcap",
                                    kOuster + "/OS-0-32-U1_v2.2.0_1024x10.json");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_FALSE(one[0].complete);
  std::set<double> columns(one[0].stamps.begin(), one[0].stamps.end());
  EXPECT_LE(columns.size(), 16u);
}

TEST(OusterRecordings, ThroughTheSequenceLayer) {
  // Captures opened as sequences: the JSON beside the capture, or given; the empty capture is
  // refused by the sequence layer with its reason.
  const std::string lb = kOuster + "/OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  SKIP_WITHOUT(lb);
  const io::Sequence seq = io::open_sequence(lb);
  ASSERT_EQ(seq.size(), 3u);
  ASSERT_TRUE(seq.sensor.has_value());
  EXPECT_EQ(seq.sensor->preset, "OS-1-128");
  EXPECT_EQ(seq.sensor->N_scan, 128);
  EXPECT_EQ(seq.sensor->Horizon_SCAN, 1024);
  const PointCloud cloud = seq.read_scan(2);
  EXPECT_GT(cloud.size(), 100000u);
  ASSERT_EQ(seq.times.size(), 3u);
  EXPECT_NEAR(seq.times[2] - seq.times[0], 0.2, 1e-3);

  io::InputOptions in;
  in.metadata = kOuster + "/OS-1-64_sensor_config_reduced.json";
  EXPECT_EQ(io::open_sequence(kOuster + "/OS-1-64_1024x10_fw20.pcap", in).size(), 1u);

  const std::string empty = kOuster + "/bad/empty_pcap.pcap";
  const std::string e = error_of([&] { (void)io::open_sequence(empty); });
  std::cout << "empty_pcap: " << e << "\n";
  EXPECT_THAT(e, HasSubstr("empty_pcap.pcap"));
  EXPECT_THAT(e, HasSubstr("holds no UDP datagrams"));
}

TEST(OusterRecordings, RealFramesLookLikeAScene) {
  // Every recording: no point inside the sensor or above its limits, all rings used, and the
  // ground below the sensor is level.
  struct File {
    std::string pcap, json;
  };
  const std::vector<File> files = {
      {"OS-2-128-U1_v2.3.0_1024x10.pcap", "OS-2-128-U1_v2.3.0_1024x10.json"},
      {"OS-0-128-U1_v2.3.0_1024x10.pcap", "OS-0-128-U1_v2.3.0_1024x10.json"},
      {"OS-1-128_v2.3.0_1024x10_lb_n3.pcap", "OS-1-128_v2.3.0_1024x10.json"},
      {"OS-1-32-G_v2.1.1_1024x10.pcap", "OS-1-32-G_v2.1.1_1024x10.json"},
      {"OS-0-32-U1_v2.2.0_1024x10.pcap", "OS-0-32-U1_v2.2.0_1024x10.json"},
  };
  for (const auto& file : files) {
    SKIP_WITHOUT(kOuster + "/" + file.pcap);
    const auto scans = decode_recording(kOuster + "/" + file.pcap, kOuster + "/" + file.json);
    ASSERT_FALSE(scans.empty()) << file.pcap;
    const Scan& s = scans[0];
    const OusterMetadata md = load_ouster_metadata(kOuster + "/" + file.json);
    const double z0 = md.lidar_to_sensor(2, 3) * 1e-3;
    std::set<int> rings;
    std::vector<double> low_z;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec3& p = s.xyz[i];
      ASSERT_GE((p - Vec3(0, 0, z0)).norm(), 0.45) << file.pcap;
      ASSERT_LE(p.norm(), 400.0) << file.pcap;
      rings.insert(s.ring[i]);
      const double horiz = std::hypot(p.x(), p.y());
      if (horiz > 2.0 && horiz < 12.0 && p.z() < z0 - 0.3) low_z.push_back(p.z());
    }
    EXPECT_GE(rings.size(), static_cast<std::size_t>(md.pixels_per_column) * 3 / 4) << file.pcap;
    ASSERT_GT(low_z.size(), 500u) << file.pcap;
    // Ground: the densest 10 cm band of the low points; its points must fit a level plane.
    std::map<int, int> bands;
    for (const double z : low_z) ++bands[static_cast<int>(std::floor(z / 0.1))];
    const int band = std::max_element(bands.begin(), bands.end(), [](auto& a, auto& b) {
                       return a.second < b.second;
                     })->first;
    std::vector<Vec3> ground;
    for (const auto& p : s.xyz) {
      const double horiz = std::hypot(p.x(), p.y());
      if (horiz > 2.0 && horiz < 12.0 && std::abs(p.z() - (band + 0.5) * 0.1) < 0.1) ground.push_back(p);
    }
    ASSERT_GT(ground.size(), 300u) << file.pcap;
    Eigen::MatrixXd A(static_cast<Eigen::Index>(ground.size()), 3);
    for (std::size_t i = 0; i < ground.size(); ++i)
      A.row(static_cast<Eigen::Index>(i)) = ground[i].transpose();
    const Eigen::MatrixXd C = A.rowwise() - A.colwise().mean();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(C, Eigen::ComputeThinV);
    const Eigen::Vector3d normal = svd.matrixV().col(2);
    const double tilt = std::acos(std::min(1.0, std::abs(normal.z()))) * 180.0 / M_PI;
    const double height = -A.col(2).mean();
    // The sensor model puts every point back on its own beam (the range image's row).
    DriverOptions o;
    o.calibration = kOuster + "/" + file.json;
    const SensorConfig model = make_ouster_scanner(o, {})->sensor();
    const BeamLookup lookup(model);
    std::size_t own_row = 0;
    for (std::size_t i = 0; i < s.size(); ++i) own_row += lookup.row(s.xyz[i]) == s.ring[i] ? 1 : 0;
    const double own = static_cast<double>(own_row) / static_cast<double>(s.size());
    std::cout << file.pcap << ": " << s.size() << " points, ground " << height
              << " m below the sensor frame, tilt " << tilt << " deg, " << ground.size() << " ground points, "
              << 100.0 * own << " % on their own row\n";
    EXPECT_GT(own, 0.995) << file.pcap;
    EXPECT_LT(tilt, 6.0) << file.pcap;
    EXPECT_GT(height, 0.2) << file.pcap;
    EXPECT_LT(height, 4.0) << file.pcap;
  }
}

}  // namespace
