// Hesai decoder (drivers/hesai.hpp): synthetic packets of every model with known distances and
// angles in and known points out, the multi-return rules, return selection, the per-channel scan
// cut, loss accounting, timing, calibration CSVs and bad input; then the 7 nebula reference
// clouds of the shared sensors folder, point for point.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>

#include "dloam/drivers/channel_cut.hpp"
#include "dloam/drivers/hesai.hpp"
#include "dloam/drivers/hesai_packet.hpp"
#include "dloam/drivers/stamp_alignment.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/pcd.hpp"

using namespace dloam;
using namespace dloam::drivers;
using hesai::Model;
using ::testing::HasSubstr;

namespace {

const std::string kSensors = DLOAM_SENSORS_DIR;
const std::string kHesai = kSensors + "/hesai/nebula";

// ---------------------------------------------------------------------------------------------
// Synthetic packets, written from the layouts of the user manuals.

struct Unit {
  std::uint16_t distance = 0;
  std::uint8_t reflectivity = 0;
};

struct Synth {
  Model model = Model::kPandarXT32;
  std::uint8_t mode = 0x37;
  int rpm = 600;
  std::uint32_t sequence = 0;
  double sensor_time = 1.6e9;          // s since 1970
  std::uint8_t dis_unit = 4;           // mm (the Pandar40P has no field: 4 mm)
  std::uint8_t mode_flag = 0;          // QT128
  std::vector<std::uint16_t> azimuth;  // per block, 0.01 deg
  std::function<Unit(int block, int channel)> unit = [](int, int) { return Unit{}; };

  [[nodiscard]] std::vector<std::uint8_t> bytes() const;
};

void put16(std::vector<std::uint8_t>& b, std::size_t at, unsigned v) {
  b[at] = static_cast<std::uint8_t>(v & 0xFF);
  b[at + 1] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
}
void put32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k)
    b[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>((v >> (8 * k)) & 0xFF);
}
void put_date(std::vector<std::uint8_t>& b, std::size_t at, double t, int year_base) {
  const auto secs = static_cast<std::time_t>(std::floor(t));
  std::tm tm{};
  gmtime_r(&secs, &tm);
  b[at] = static_cast<std::uint8_t>(tm.tm_year + 1900 - year_base);
  b[at + 1] = static_cast<std::uint8_t>(tm.tm_mon + 1);
  b[at + 2] = static_cast<std::uint8_t>(tm.tm_mday);
  b[at + 3] = static_cast<std::uint8_t>(tm.tm_hour);
  b[at + 4] = static_cast<std::uint8_t>(tm.tm_min);
  b[at + 5] = static_cast<std::uint8_t>(tm.tm_sec);
}
std::uint32_t micros_of(double t) {
  return static_cast<std::uint32_t>(std::llround((t - std::floor(t)) * 1e6)) % 1000000u;
}

std::vector<std::uint8_t> Synth::bytes() const {
  const hesai::ModelInfo& info = hesai::model_info(model);
  const int blocks = info.blocks, lasers = info.channels;
  EXPECT_EQ(static_cast<int>(azimuth.size()), blocks);
  std::vector<std::uint8_t> b;
  auto fill_units = [&](std::size_t start, std::size_t unit_size) {
    for (int k = 0; k < blocks; ++k) {
      const std::size_t at = start + static_cast<std::size_t>(k) * (2 + unit_size * lasers);
      put16(b, at, azimuth[static_cast<std::size_t>(k)]);
      for (int c = 0; c < lasers; ++c) {
        const Unit u = unit(k, c);
        const std::size_t p = at + 2 + unit_size * static_cast<std::size_t>(c);
        put16(b, p, u.distance);
        b[p + 2] = u.reflectivity;
      }
    }
  };
  switch (model) {
    case Model::kPandar40P: {
      b.assign(1262, 0);
      for (int k = 0; k < 10; ++k) {
        b[static_cast<std::size_t>(k) * 124] = 0xFF;
        b[static_cast<std::size_t>(k) * 124 + 1] = 0xEE;
      }
      for (int k = 0; k < 10; ++k) {
        const std::size_t at = static_cast<std::size_t>(k) * 124 + 2;
        put16(b, at, azimuth[static_cast<std::size_t>(k)]);
        for (int c = 0; c < 40; ++c) {
          const Unit u = unit(k, c);
          put16(b, at + 2 + 3 * static_cast<std::size_t>(c), u.distance);
          b[at + 4 + 3 * static_cast<std::size_t>(c)] = u.reflectivity;
        }
      }
      const std::size_t t = 1240;
      put16(b, t + 8, static_cast<unsigned>(rpm));
      put32(b, t + 10, micros_of(sensor_time));
      b[t + 14] = mode;
      b[t + 15] = 0x42;
      put_date(b, t + 16, sensor_time, 2000);
      break;
    }
    case Model::kPandar64: {
      b.assign(1198, 0);
      b[0] = 0xEE, b[1] = 0xFF, b[2] = 64, b[3] = 6, b[5] = dis_unit;
      fill_units(8, 3);
      const std::size_t t = 8 + 6 * 194;
      put16(b, t + 8, static_cast<unsigned>(rpm));
      put32(b, t + 10, micros_of(sensor_time));
      b[t + 14] = mode;
      b[t + 15] = 0x42;
      put_date(b, t + 16, sensor_time, 1900);
      put32(b, t + 22, sequence);
      break;
    }
    case Model::kPandarQT64: {
      b.assign(1072, 0);
      const std::uint8_t h[12] = {0xEE, 0xFF, 3, 1, 0, 0, 64, 4, 0, dis_unit, 2, 1};
      std::copy(h, h + 12, b.begin());
      fill_units(12, 4);
      const std::size_t t = 12 + 4 * 258;
      put16(b, t + 10, static_cast<unsigned>(rpm));
      put32(b, t + 12, micros_of(sensor_time));
      b[t + 16] = mode;
      b[t + 17] = 0x42;
      put_date(b, t + 18, sensor_time, 1900);
      put32(b, t + 24, sequence);
      break;
    }
    case Model::kPandarQT128: {
      b.assign(1127, 0);
      const std::uint8_t h[12] = {0xEE, 0xFF, 3, 2, 0, 0, 128, 2, 0, dis_unit, 2, 0x0D};
      std::copy(h, h + 12, b.begin());
      fill_units(12, 4);
      const std::size_t body_end = 12 + 2 * 514;
      put32(b, body_end, hesai::crc32_mpeg2(b.data() + 12, body_end - 12));
      const std::size_t t = body_end + 4 + 17;
      b[t + 5] = mode_flag;
      b[t + 12] = mode;
      put16(b, t + 13, static_cast<unsigned>(rpm));
      put_date(b, t + 15, sensor_time, 1900);
      put32(b, t + 21, micros_of(sensor_time));
      b[t + 25] = 0x42;
      put32(b, t + 26, sequence);
      put32(b, t + 30, hesai::crc32_mpeg2(b.data() + t, 30));
      break;
    }
    default: {  // XT family
      const std::size_t stride = 2 + 4 * static_cast<std::size_t>(lasers);
      const std::size_t t = 12 + stride * static_cast<std::size_t>(blocks);
      b.assign(t + 28, 0);
      const std::uint8_t h[12] = {
          0xEE, 0xFF,     6, 1, 0, 0, static_cast<std::uint8_t>(lasers), static_cast<std::uint8_t>(blocks),
          0,    dis_unit, 2, 1};
      std::copy(h, h + 12, b.begin());
      fill_units(12, 4);
      b[t + 10] = mode;
      put16(b, t + 11, static_cast<unsigned>(rpm));
      put_date(b, t + 13, sensor_time, 1900);
      put32(b, t + 19, micros_of(sensor_time));
      b[t + 23] = 0x42;
      put32(b, t + 24, sequence);
      break;
    }
  }
  return b;
}

Packet as_packet(const std::vector<std::uint8_t>& bytes, double stamp = 0.0,
                 const std::string& where = "test") {
  Packet p;
  p.data = bytes.data();
  p.size = bytes.size();
  p.stamp = stamp;
  p.where = where;
  return p;
}

/// Every unit at `distance` m (raw in 4 mm) with reflectivity 100, blocks of one group sharing
/// the azimuth.
Synth uniform_packet(Model model, std::uint8_t mode, std::uint16_t first_azimuth, int step, double distance) {
  Synth s;
  s.model = model;
  s.mode = mode;
  const int blocks = hesai::model_info(model).blocks;
  const int returns = hesai::return_layout(model, mode).returns;
  for (int k = 0; k < blocks; ++k)
    s.azimuth.push_back(static_cast<std::uint16_t>((first_azimuth + step * (k / returns)) % 36000));
  const auto raw = static_cast<std::uint16_t>(std::lround(distance / 0.004));
  s.unit = [raw](int, int) { return Unit{raw, 100}; };
  return s;
}

ScannerOptions all_returns() {
  ScannerOptions o;
  o.returns = ReturnMode::kAll;
  return o;
}

std::unique_ptr<HesaiScanner> scanner_for(Model model, const ScannerOptions& options = all_returns(),
                                          const HesaiOptions& hesai_options = {}) {
  return std::make_unique<HesaiScanner>(model, hesai::nominal_calibration(model), options, hesai_options);
}

/// Azimuth (deg, clockwise from the front, [0, 360)) of a point in dloam's frame.
double azimuth_deg(const Vec3& p) {
  double a = std::atan2(-p.y(), p.x()) * 180.0 / M_PI;
  if (a < 0.0) a += 360.0;
  return a;
}

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// ---------------------------------------------------------------------------------------------
// The nebula bags: pandar_msgs/msg/PandarScan messages on /pandar_packets.

struct BagPacket {
  std::vector<std::uint8_t> bytes;
  double stamp = 0.0;
  std::size_t message = 0, index = 0;
};
struct Bag {
  std::vector<std::int64_t> timestamps;  // per message, ns
  std::vector<BagPacket> packets;
};

Bag read_pandar_bag(const std::string& folder) {
  const io::Bag bag(folder);
  const std::string topic = "/pandar_packets", type = "pandar_msgs/msg/PandarScan";
  Bag out;
  for (std::size_t k = 0; k < bag.message_count(topic); ++k) {
    const std::int64_t t = bag.message_time_ns(topic, k);
    out.timestamps.push_back(t);
    const std::vector<std::uint8_t> data = bag.read(topic, k);
    const io::PacketMessage m =
        io::decode_packet_message(type, data.data(), data.size(), 1e-9 * t, bag.where(topic, k));
    for (std::size_t i = 0; i < m.packets.size(); ++i) {
      const io::PacketSlice& s = m.packets[i];
      BagPacket p;
      p.bytes.assign(data.begin() + static_cast<std::ptrdiff_t>(s.offset),
                     data.begin() + static_cast<std::ptrdiff_t>(s.offset + s.size));
      p.stamp = s.stamp;
      p.message = k;
      p.index = i;
      out.packets.push_back(std::move(p));
    }
  }
  return out;
}

std::string bag_folder(const std::string& model_dir) {
  for (const auto& e : std::filesystem::directory_iterator(model_dir))
    if (e.is_directory()) return e.path().string();
  return {};
}

}  // namespace

// =============================================================================================
// Packets

TEST(HesaiPacket, EveryModelIsKnownByItsHeaderOrSize) {
  for (const Model m : hesai::all_models()) {
    const std::vector<std::uint8_t> bytes = uniform_packet(m, 0x39, 1000, 20, 5.0).bytes();
    const Packet p = as_packet(bytes);
    EXPECT_TRUE(looks_like_hesai(p)) << hesai::model_name(m);
    EXPECT_EQ(hesai::identify_model(p), m) << hesai::model_name(m);
    const hesai::PacketView v = hesai::parse_packet(p, m);
    EXPECT_EQ(v.layout.returns, 2);
    EXPECT_EQ(v.motor_rpm, 600);
    EXPECT_EQ(v.azimuth(0), 1000);
  }
}

TEST(HesaiPacket, SensorTimeFromTheDateAndMicroseconds) {
  Synth s = uniform_packet(Model::kPandarXT32, 0x37, 0, 18, 5.0);
  s.sensor_time = 1564012800.25;  // 2019-07-25 00:00:00.25 UTC
  const std::vector<std::uint8_t> bytes = s.bytes();
  EXPECT_NEAR(hesai::parse_packet(as_packet(bytes), Model::kPandarXT32).sensor_time, 1564012800.25, 1e-6);
  Synth f = uniform_packet(Model::kPandar40P, 0x37, 0, 20, 5.0);
  f.sensor_time = 1504656000.5;  // 2017-09-06
  const std::vector<std::uint8_t> fb = f.bytes();
  EXPECT_NEAR(hesai::parse_packet(as_packet(fb), Model::kPandar40P).sensor_time, 1504656000.5, 1e-6);
}

TEST(HesaiPacket, GpsPacketsAreIgnoredAndCounted) {
  std::vector<std::uint8_t> gps(512, 0);
  gps[0] = 0xFF, gps[1] = 0xEE;
  const Packet p = as_packet(gps);
  EXPECT_FALSE(looks_like_hesai(p));
  auto scanner = scanner_for(Model::kPandar40P);
  std::vector<Scan> done;
  scanner->add(p, done);
  EXPECT_EQ(scanner->ignored_packets(), 1u);
  EXPECT_EQ(scanner->packets(), 0u);
  EXPECT_THAT(scanner->describe(), HasSubstr("1 ignored"));
}

TEST(HesaiPacket, WrongSizeForItsHeaderIsAnError) {
  std::vector<std::uint8_t> bytes = uniform_packet(Model::kPandarXT32, 0x37, 0, 18, 5.0).bytes();
  bytes.resize(bytes.size() - 3);
  auto scanner = scanner_for(Model::kPandarXT32);
  std::vector<Scan> done;
  try {
    scanner->add(as_packet(bytes, 0.0, "drive.db3: message 2 packet 7"), done);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("drive.db3: message 2 packet 7"));
    EXPECT_THAT(e.what(), HasSubstr("1077 bytes"));
    EXPECT_THAT(e.what(), HasSubstr("1080"));
  }
  std::vector<std::uint8_t> forty = uniform_packet(Model::kPandar40P, 0x37, 0, 20, 5.0).bytes();
  forty.push_back(0);
  EXPECT_THROW(hesai::identify_model(as_packet(forty)), InputError);
  forty.pop_back();
  forty[124 * 3] = 0;  // block 3 marker
  EXPECT_THAT([&] { hesai::parse_packet(as_packet(forty), Model::kPandar40P); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("block 3")));
}

TEST(HesaiPacket, UnknownProtocolVersionIsAnError) {
  std::vector<std::uint8_t> bytes = uniform_packet(Model::kPandarXT32, 0x37, 0, 18, 5.0).bytes();
  bytes[2] = 7, bytes[3] = 9;
  EXPECT_TRUE(looks_like_hesai(as_packet(bytes)));  // magic only; the decoder reports the version
  EXPECT_THAT([&] { hesai::identify_model(as_packet(bytes, 0.0, "x.pcap: packet 3")); },
              ::testing::ThrowsMessage<InputError>(AllOf(HasSubstr("x.pcap: packet 3"), HasSubstr("7.9"))));
  bytes[2] = 1, bytes[3] = 4;
  EXPECT_THAT([&] { hesai::identify_model(as_packet(bytes)); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("not supported")));
  std::vector<std::uint8_t> other(600, 0x55);
  EXPECT_FALSE(looks_like_hesai(as_packet(other)));
  EXPECT_THROW(hesai::identify_model(as_packet(other)), InputError);
  // A Velodyne data packet also starts with FF EE blocks, but has 1206 bytes; Ouster's start 01 00.
  std::vector<std::uint8_t> velodyne(1206, 0);
  for (std::size_t k = 0; k < 12; ++k) velodyne[100 * k] = 0xFF, velodyne[100 * k + 1] = 0xEE;
  EXPECT_FALSE(looks_like_hesai(as_packet(velodyne)));
  std::vector<std::uint8_t> ouster(8448, 0);
  ouster[0] = 1;
  EXPECT_FALSE(looks_like_hesai(as_packet(ouster)));
}

TEST(HesaiPacket, DamagedPacketsGiveInputErrorsOrFinitePoints) {
  // Random bytes changed in valid packets, and truncated packets, of every model: each one is
  // decoded or rejected with an InputError naming it; whatever is decoded is finite.
  std::mt19937 rng(11);
  for (const Model m : hesai::all_models()) {
    auto scanner = scanner_for(m);
    std::vector<Scan> done;
    std::size_t errors = 0;
    for (int k = 0; k < 400; ++k) {
      Synth s =
          uniform_packet(m, k % 2 ? 0x39 : 0x37, static_cast<std::uint16_t>((k * 300) % 36000), 20, 12.0);
      s.sequence = static_cast<std::uint32_t>(k);
      std::vector<std::uint8_t> bytes = s.bytes();
      const int changes = static_cast<int>(rng() % 8);
      for (int c = 0; c < changes; ++c) bytes[rng() % bytes.size()] = static_cast<std::uint8_t>(rng());
      if (k % 5 == 0) bytes.resize(rng() % bytes.size());
      const std::string where = "packet " + std::to_string(k);
      try {
        scanner->add(as_packet(bytes, 0.0, where), done);
      } catch (const InputError& e) {
        ++errors;
        EXPECT_THAT(e.what(), HasSubstr(where));
      }
    }
    scanner->finish(done);
    EXPECT_GT(errors, 0u) << hesai::model_name(m);
    std::size_t points = 0;
    for (const Scan& scan : done) {
      points += scan.size();
      for (std::size_t i = 0; i < scan.size(); ++i) {
        ASSERT_TRUE(scan.xyz[i].allFinite()) << hesai::model_name(m);
        ASSERT_TRUE(std::isfinite(scan.stamps[i])) << hesai::model_name(m);
        ASSERT_LT(scan.ring[i], hesai::model_info(m).channels);
      }
    }
    EXPECT_GT(points, 0u) << hesai::model_name(m);
  }
}

TEST(HesaiPacket, Crc32Mpeg2MatchesTheBitwiseDefinition) {
  // MSB first, polynomial 0x04C11DB7, initial value all ones, no final xor; check value of
  // "123456789" is 0x0376E6E7.
  const std::string check = "123456789";
  EXPECT_EQ(hesai::crc32_mpeg2(reinterpret_cast<const std::uint8_t*>(check.data()), check.size()),
            0x0376E6E7u);
  std::mt19937 rng(5);
  for (std::size_t n : {0u, 1u, 7u, 15u, 16u, 17u, 31u, 1028u}) {
    std::vector<std::uint8_t> d(n);
    for (auto& b : d) b = static_cast<std::uint8_t>(rng());
    std::uint32_t crc = 0xFFFFFFFFu;
    for (const std::uint8_t b : d) {
      crc ^= static_cast<std::uint32_t>(b) << 24;
      for (int k = 0; k < 8; ++k) crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
    EXPECT_EQ(hesai::crc32_mpeg2(d.data(), d.size()), crc) << n << " bytes";
  }
}

TEST(HesaiPacket, UnknownReturnModeAndBadAzimuthAreErrors) {
  Synth s = uniform_packet(Model::kPandarQT64, 0x37, 0, 60, 5.0);
  s.mode = 0x20;
  std::vector<std::uint8_t> bytes = s.bytes();
  EXPECT_THAT([&] { hesai::parse_packet(as_packet(bytes), Model::kPandarQT64); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("return mode 0x20")));
  s.mode = 0x37;
  s.azimuth[2] = 36000;
  bytes = s.bytes();
  EXPECT_THAT([&] { hesai::parse_packet(as_packet(bytes), Model::kPandarQT64); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("azimuth 36000")));
}

TEST(HesaiPacket, PacketOfAnotherModelInTheStreamIsAnError) {
  const std::vector<std::uint8_t> bytes = uniform_packet(Model::kPandarXT16, 0x37, 0, 18, 5.0).bytes();
  auto scanner = scanner_for(Model::kPandarXT32);
  std::vector<Scan> done;
  EXPECT_THAT([&] { scanner->add(as_packet(bytes, 0.0, "bag: packet 9"), done); },
              ::testing::ThrowsMessage<InputError>(
                  AllOf(HasSubstr("bag: packet 9"), HasSubstr("PandarXT16"), HasSubstr("PandarXT32"))));
}

TEST(HesaiPacket, Qt128CrcMismatchIsCountedAndNotDecoded) {
  Synth s = uniform_packet(Model::kPandarQT128, 0x37, 100, 40, 5.0);
  std::vector<std::uint8_t> bytes = s.bytes();
  EXPECT_TRUE(hesai::parse_packet(as_packet(bytes), Model::kPandarQT128).crc_ok);
  bytes[500] ^= 0x10;
  EXPECT_FALSE(hesai::parse_packet(as_packet(bytes), Model::kPandarQT128).crc_ok);
  auto scanner = scanner_for(Model::kPandarQT128);
  std::vector<Scan> done;
  scanner->add(as_packet(bytes), done);
  scanner->finish(done);
  EXPECT_EQ(scanner->corrupt_packets(), 1u);
  EXPECT_TRUE(done.empty());
  EXPECT_THAT(scanner->describe(), HasSubstr("bad CRC"));
}

// =============================================================================================
// Points

TEST(HesaiPoints, KnownDistanceAndAnglesGiveKnownPoints) {
  // One channel of each model at a known distance; elevation and azimuth offset from the nominal
  // table; point in dloam's frame x front, y left: (d cos el cos az, -d cos el sin az, d sin el).
  for (const Model m : hesai::all_models()) {
    const hesai::Calibration cal = hesai::nominal_calibration(m);
    const int channel = hesai::model_info(m).channels / 3;
    Synth s = uniform_packet(m, 0x37, 4321, 20, 0.0);
    s.dis_unit = m == Model::kPandarXT32M ? 5 : 4;
    const double unit = m == Model::kPandar40P ? 0.004 : s.dis_unit * 1e-3;
    s.unit = [channel](int block, int c) { return c == channel && block == 0 ? Unit{2345, 77} : Unit{}; };
    const std::vector<std::uint8_t> bytes = s.bytes();
    auto scanner = scanner_for(m);
    std::vector<Scan> done;
    scanner->add(as_packet(bytes), done);
    scanner->finish(done);
    ASSERT_EQ(done.size(), 1u) << hesai::model_name(m);
    ASSERT_EQ(done[0].size(), 1u) << hesai::model_name(m);
    const double d = 2345 * unit;
    const double el = cal.elevation_deg[static_cast<std::size_t>(channel)] * M_PI / 180.0;
    const double az = (43.21 + cal.azimuth_deg[static_cast<std::size_t>(channel)]) * M_PI / 180.0;
    const Vec3 expected(d * std::cos(el) * std::cos(az), -d * std::cos(el) * std::sin(az), d * std::sin(el));
    EXPECT_LT((done[0].xyz[0] - expected).norm(), 1e-9) << hesai::model_name(m);
    EXPECT_EQ(done[0].intensity[0], 77.0f);
    EXPECT_EQ(done[0].ring[0], scanner->rings()[static_cast<std::size_t>(channel)]);
    EXPECT_EQ(done[0].return_id[0], 0);
    EXPECT_FALSE(done[0].complete);
  }
}

TEST(HesaiPoints, RingsAreTheElevationOrder) {
  for (const Model m : hesai::all_models()) {
    auto scanner = scanner_for(m);
    const hesai::Calibration& cal = scanner->calibration();
    const SensorConfig s = scanner->sensor();
    ASSERT_EQ(s.N_scan, cal.channels());
    for (int c = 0; c < cal.channels(); ++c)
      EXPECT_EQ(s.beam_elevations_deg[scanner->rings()[static_cast<std::size_t>(c)]],
                cal.elevation_deg[static_cast<std::size_t>(c)]);
    EXPECT_NO_THROW(s.validate()) << hesai::model_name(m);
  }
}

namespace {
/// Decodes one dual packet of `model` whose channel 0 has the returns `a` (block 0) and `b`
/// (block 1) and returns the kept (return_id, distance in m) pairs.
std::vector<std::pair<int, double>> dual_returns(Model model, std::uint8_t mode, Unit a, Unit b,
                                                 ReturnMode want = ReturnMode::kAll, ScannerOptions o = {}) {
  Synth s = uniform_packet(model, mode, 5000, 18, 0.0);
  s.unit = [a, b](int block, int c) { return c != 0 || block > 1 ? Unit{} : (block == 0 ? a : b); };
  const std::vector<std::uint8_t> bytes = s.bytes();
  o.returns = want;
  auto scanner = scanner_for(model, o);
  std::vector<Scan> done;
  scanner->add(as_packet(bytes), done);
  scanner->finish(done);
  std::vector<std::pair<int, double>> kept;
  for (const Scan& scan : done)
    for (std::size_t i = 0; i < scan.size(); ++i)
      kept.emplace_back(scan.return_id[i], std::round(scan.xyz[i].norm() * 1000.0) / 1000.0);
  return kept;
}
}  // namespace

TEST(HesaiReturns, DuplicateReturnsKeepOnlyTheLast) {
  using P = std::vector<std::pair<int, double>>;
  // Same distance and reflectivity: only block 1 (the group's last) is kept.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {2500, 50}), (P{{1, 10.0}}));
  // Same distance, other reflectivity: closer than 0.1 m, so again only the last.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {2500, 60}), (P{{1, 10.0}}));
  // 0.096 m apart (24 x 4 mm): near-duplicate, only the last.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {2524, 60}), (P{{1, 10.096}}));
  // 0.2 m apart: both, in block order.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {2550, 60}), (P{{0, 10.0}, {1, 10.2}}));
  // The last return invalid (distance 0) still makes block 0 a near-duplicate only if close: 10 m
  // is far from 0, so block 0 is kept.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {0, 0}), (P{{0, 10.0}}));
  // Distance 0 and beyond the sensor's range (XT32: 120 m) are dropped.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {0, 50}, {0, 50}), (P{}));
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {31000, 50}, {2550, 60}), (P{{1, 10.2}}));
  // A configured range within the sensor's.
  ScannerOptions o;
  o.min_range = 10.1;
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x39, {2500, 50}, {2550, 60}, ReturnMode::kAll, o),
            (P{{1, 10.2}}));
}

TEST(HesaiReturns, NearDuplicateSeparationIsAnOption) {
  Synth s = uniform_packet(Model::kPandarXT32, 0x39, 5000, 18, 0.0);
  s.unit = [](int block, int c) {
    return c != 0 || block > 1 ? Unit{} : Unit{block == 0 ? std::uint16_t{2500} : std::uint16_t{2540}, 9};
  };
  const std::vector<std::uint8_t> bytes = s.bytes();
  for (const double sep : {0.1, 0.2}) {
    HesaiOptions h;
    h.multi_return_separation_m = sep;
    auto scanner = scanner_for(Model::kPandarXT32, all_returns(), h);
    std::vector<Scan> done;
    scanner->add(as_packet(bytes), done);
    scanner->finish(done);
    ASSERT_EQ(done.size(), 1u);
    EXPECT_EQ(done[0].size(), sep < 0.16 ? 2u : 1u) << sep;
  }
}

TEST(HesaiReturns, SelectedReturnFollowsTheModesLayout) {
  using P = std::vector<std::pair<int, double>>;
  const Unit near{2500, 30}, far{5000, 90};
  // 0x39 last+strongest: block 0 last; block 1 strongest unless block 0 is.
  EXPECT_EQ(dual_returns(Model::kPandar64, 0x39, far, near, ReturnMode::kLast), (P{{0, 20.0}}));
  EXPECT_EQ(dual_returns(Model::kPandar64, 0x39, far, near, ReturnMode::kStrongest), (P{{0, 20.0}}));
  EXPECT_EQ(dual_returns(Model::kPandar64, 0x39, {5000, 10}, near, ReturnMode::kStrongest), (P{{1, 10.0}}));
  // Not reported by 0x39: the first is the nearest valid return.
  EXPECT_EQ(dual_returns(Model::kPandar64, 0x39, far, near, ReturnMode::kFirst), (P{{1, 10.0}}));
  // 0x3b first+last: QT64 stores first, last; the XT16/XT32 last, first.
  EXPECT_EQ(dual_returns(Model::kPandarQT64, 0x3b, near, far, ReturnMode::kFirst), (P{{0, 10.0}}));
  EXPECT_EQ(dual_returns(Model::kPandarQT64, 0x3b, near, far, ReturnMode::kLast), (P{{1, 20.0}}));
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x3b, far, near, ReturnMode::kFirst), (P{{1, 10.0}}));
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x3b, far, near, ReturnMode::kLast), (P{{0, 20.0}}));
  // 0x3b has no strongest: the most reflective valid return.
  EXPECT_EQ(dual_returns(Model::kPandarXT32, 0x3b, far, near, ReturnMode::kStrongest), (P{{0, 20.0}}));
  // 0x3c first+strongest (XT32M).
  EXPECT_EQ(dual_returns(Model::kPandarXT32M, 0x3c, near, far, ReturnMode::kFirst), (P{{0, 10.0}}));
  EXPECT_EQ(dual_returns(Model::kPandarXT32M, 0x3c, near, far, ReturnMode::kStrongest), (P{{1, 20.0}}));
  // A selected return that is invalid gives no point (no fallback to the other one).
  EXPECT_EQ(dual_returns(Model::kPandar64, 0x39, {0, 0}, near, ReturnMode::kLast), (P{}));
}

TEST(HesaiReturns, TripleReturnGroupsOfThreeBlocks) {
  // XT32M 0x3d: 6 blocks = 2 firings of (first, last, strongest).
  Synth s = uniform_packet(Model::kPandarXT32M, 0x3d, 1000, 18, 0.0);
  s.dis_unit = 5;
  s.unit = [](int block, int c) {
    if (c != 3) return Unit{};
    const std::uint16_t d[3] = {1000, 3000, 2000};
    return Unit{d[block % 3], static_cast<std::uint8_t>(block % 3 == 2 ? 200 : 20)};
  };
  const std::vector<std::uint8_t> bytes = s.bytes();
  for (const ReturnMode want :
       {ReturnMode::kAll, ReturnMode::kFirst, ReturnMode::kLast, ReturnMode::kStrongest}) {
    ScannerOptions o;
    o.returns = want;
    auto scanner = scanner_for(Model::kPandarXT32M, o);
    std::vector<Scan> done;
    scanner->add(as_packet(bytes), done);
    scanner->finish(done);
    ASSERT_EQ(done.size(), 1u);
    const Scan& scan = done[0];
    if (want == ReturnMode::kAll) {
      ASSERT_EQ(scan.size(), 6u);
      EXPECT_NEAR(scan.xyz[0].norm(), 5.0, 1e-9);
      EXPECT_NEAR(scan.xyz[1].norm(), 15.0, 1e-9);
      EXPECT_NEAR(scan.xyz[2].norm(), 10.0, 1e-9);
    } else {
      ASSERT_EQ(scan.size(), 2u);
      const double expected = want == ReturnMode::kFirst ? 5.0 : want == ReturnMode::kLast ? 15.0 : 10.0;
      EXPECT_NEAR(scan.xyz[0].norm(), expected, 1e-9);
      EXPECT_NEAR(scan.xyz[1].norm(), expected, 1e-9);
    }
  }
}

TEST(HesaiReturns, SingleReturnStreamGivesItsOnlyReturn) {
  for (const ReturnMode want :
       {ReturnMode::kFirst, ReturnMode::kLast, ReturnMode::kStrongest, ReturnMode::kAll}) {
    const std::vector<std::uint8_t> bytes = uniform_packet(Model::kPandarXT16, 0x37, 100, 18, 7.0).bytes();
    ScannerOptions o;
    o.returns = want;
    auto scanner = scanner_for(Model::kPandarXT16, o);
    std::vector<Scan> done;
    scanner->add(as_packet(bytes), done);
    scanner->finish(done);
    ASSERT_EQ(done.size(), 1u);
    EXPECT_EQ(done[0].size(), 8u * 16u);
  }
}

TEST(HesaiPoints, FiringTimeAzimuthTurnsEachChannelByItsFiringOffset) {
  // XT32 channel 31 fires 368 + 31 x 1512 ns after its block starts: at 600 rpm (3600 deg/s)
  // the rotor has turned 0.1701 deg more.
  Synth s = uniform_packet(Model::kPandarXT32, 0x37, 9000, 18, 0.0);
  s.unit = [](int block, int c) { return block == 0 && c == 31 ? Unit{2500, 1} : Unit{}; };
  const std::vector<std::uint8_t> bytes = s.bytes();
  double az[2];
  for (int on = 0; on < 2; ++on) {
    HesaiOptions h;
    h.firing_time_azimuth = on == 1;
    auto scanner = scanner_for(Model::kPandarXT32, all_returns(), h);
    std::vector<Scan> done;
    scanner->add(as_packet(bytes), done);
    scanner->finish(done);
    ASSERT_EQ(done.size(), 1u);
    ASSERT_EQ(done[0].size(), 1u);
    az[on] = azimuth_deg(done[0].xyz[0]);
  }
  EXPECT_NEAR(az[0], 90.0 + hesai::nominal_calibration(Model::kPandarXT32).azimuth_deg[31], 1e-9);
  EXPECT_NEAR(az[1] - az[0], (368 + 31 * 1512) * 1e-9 * 3600.0, 1e-9);
}

// =============================================================================================
// Times

TEST(HesaiTimes, PointTimesAreThePacketTimePlusTheFiringOffsets) {
  // XT32 single return: block k of 8 starts 5.632 us - 50 us x (7 - k) from the packet time,
  // channel c 0.368 + 1.512 c us later. Packet stamps = sensor time + 2 s + delays >= 0.3 ms:
  // the offset is the least-delayed packet's, 2.0003 s.
  auto scanner = scanner_for(Model::kPandarXT32);
  std::vector<Scan> done;
  std::vector<std::vector<std::uint8_t>> keep;
  const double t0 = 1.6e9 + 0.5;
  for (int k = 0; k < 10; ++k) {
    Synth s = uniform_packet(Model::kPandarXT32, 0x37, static_cast<std::uint16_t>(1000 + 144 * k), 18, 5.0);
    s.sequence = static_cast<std::uint32_t>(k);
    s.sensor_time = t0 + 400e-6 * k;
    keep.push_back(s.bytes());
    const double delay = k == 4 ? 0.3e-3 : 0.3e-3 + 1e-3 * (k % 3 + 1);
    scanner->add(as_packet(keep.back(), s.sensor_time + 2.0 + delay), done);
  }
  scanner->finish(done);
  ASSERT_EQ(done.size(), 1u);
  const Scan& scan = done[0];
  ASSERT_EQ(scan.size(), 10u * 8u * 32u);
  // Packet 9's points (the offset is then the minimum over packets 0..9: 2.0003 s).
  const std::size_t first = 9u * 256u;
  for (int b = 0; b < 8; ++b)
    for (int c = 0; c < 32; ++c) {
      const double expected = t0 + 400e-6 * 9 + 2.0003 + (5632 - 50000 * (7 - b) + 368 + 1512 * c) * 1e-9;
      EXPECT_NEAR(scan.stamps[first + static_cast<std::size_t>(b * 32 + c)], expected, 1e-6);
    }
  EXPECT_NEAR(scan.start, t0 + 2.0013 + (5632 - 350000 + 368) * 1e-9, 1e-6);  // packet 0: offset 2.0013
  EXPECT_EQ(scan.first_packet, 0u);
  EXPECT_EQ(scan.last_packet, 9u);
}

TEST(HesaiTimes, StampAlignmentFollowsClockJumps) {
  StampAlignment a(1.0, 1.0);
  EXPECT_NEAR(a.update(100.002, 10.0), 90.002, 1e-12);
  EXPECT_NEAR(a.update(100.1005, 10.1), 90.0005, 1e-12);  // less delayed
  EXPECT_NEAR(a.update(100.204, 10.2), 90.0005, 1e-12);   // bunched: the minimum stays
  EXPECT_NEAR(a.update(102.0, 11.9), 90.1, 1e-12);        // the window has moved on
  EXPECT_NEAR(a.update(102.1, 1.0), 101.1, 1e-12);        // sensor clock jumped back: start over
  EXPECT_EQ(StampAlignment().update(0.0, 5.0), 0.0);      // no recording times
}

// =============================================================================================
// Scan cut

namespace {
struct Stream {
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<Scan> scans;
};

/// `packets` single-return packets of `model` from block azimuth `start` (0.01 deg) in steps of
/// `step`, every unit at 10 m; `skip` packets (by index) are left out (lost).
Stream rotate(Model model, int start, int step, int packets, const std::set<int>& skip = {},
              const hesai::Calibration* calibration = nullptr, bool with_sequence = true) {
  Stream s;
  const hesai::ModelInfo& info = hesai::model_info(model);
  HesaiScanner scanner(model, calibration ? *calibration : hesai::nominal_calibration(model), all_returns());
  for (int k = 0; k < packets; ++k) {
    Synth p = uniform_packet(
        model, 0x37, static_cast<std::uint16_t>((start + step * info.blocks * k) % 36000), step, 10.0);
    p.sequence = with_sequence ? static_cast<std::uint32_t>(k) : 0u;
    p.sensor_time = 1.6e9 + k * info.blocks * step / 100.0 / 3600.0;
    if (skip.count(k)) continue;
    s.bytes.push_back(p.bytes());
    scanner.add(as_packet(s.bytes.back(), 0.0, "packet " + std::to_string(k)), s.scans);
  }
  scanner.finish(s.scans);
  return s;
}
}  // namespace

TEST(HesaiCut, EachChannelLeavesTheScanWhereItsOwnAzimuthCrossesZero) {
  // QT128 offsets reach +-10 deg: a cut at the block azimuth would split rings. 0.4 deg steps,
  // 900 firings a turn, 2.5 turns from 100 deg.
  const Stream s = rotate(Model::kPandarQT128, 10000, 40, 1125);
  ASSERT_EQ(s.scans.size(), 3u);
  EXPECT_FALSE(s.scans[0].complete);
  EXPECT_TRUE(s.scans[1].complete);
  EXPECT_FALSE(s.scans[2].complete);
  const Scan& full = s.scans[1];
  // Every channel fired 900 times, once at each of its corrected azimuths, none split.
  std::map<int, std::vector<double>> by_ring;
  for (std::size_t i = 0; i < full.size(); ++i) by_ring[full.ring[i]].push_back(azimuth_deg(full.xyz[i]));
  ASSERT_EQ(by_ring.size(), 128u);
  for (auto& [ring, az] : by_ring) {
    ASSERT_EQ(az.size(), 900u) << "ring " << ring;
    // In firing order the azimuth rises from just past 0 to just below 360: no wrap inside.
    for (std::size_t i = 1; i < az.size(); ++i)
      ASSERT_GT(az[i], az[i - 1]) << "ring " << ring << " firing " << i;
    EXPECT_LT(az.front(), 0.4 + 1e-6) << "ring " << ring;
    EXPECT_GT(az.back(), 360.0 - 0.4 - 1e-6) << "ring " << ring;
  }
}

TEST(HesaiCut, CutAzimuthItselfBelongsToTheEndingScan) {
  // XT16: no offsets; the firing at exactly 0 deg ends the scan, 0.18 deg starts the next.
  const Stream s = rotate(Model::kPandarXT16, 36000 - 18 * 8 * 5, 18, 300);
  ASSERT_GE(s.scans.size(), 2u);
  const Scan& first = s.scans[0];
  ASSERT_EQ(first.size(), 16u * 8u * 5u + 16u);  // 5 packets + the firing at 0 of the next
  EXPECT_NEAR(azimuth_deg(first.xyz.back()), 0.0, 1e-9);
  const Scan& second = s.scans[1];
  EXPECT_NEAR(azimuth_deg(second.xyz.front()), 0.18, 1e-9);
  ASSERT_EQ(second.size(), 16u * 2000u);
  EXPECT_TRUE(second.complete);
}

TEST(HesaiCut, CutAtAnotherAzimuth) {
  ScannerOptions o = all_returns();
  o.cut_azimuth_deg = 90.0;
  HesaiScanner scanner(Model::kPandarXT32, hesai::nominal_calibration(Model::kPandarXT32), o);
  std::vector<Scan> scans;
  std::vector<std::vector<std::uint8_t>> keep;
  for (int k = 0; k < 600; ++k) {
    Synth p =
        uniform_packet(Model::kPandarXT32, 0x37, static_cast<std::uint16_t>((144 * k) % 36000), 18, 10.0);
    p.sequence = static_cast<std::uint32_t>(k);
    keep.push_back(p.bytes());
    scanner.add(as_packet(keep.back()), scans);
  }
  ASSERT_EQ(scans.size(), 3u);  // [0, 90], (90, 450], (450, 810] deg
  EXPECT_FALSE(scans[0].complete);
  EXPECT_TRUE(scans[1].complete);
  ASSERT_EQ(scans[1].size(), 32u * 2000u);
  const double a = azimuth_deg(scans[1].xyz.front());
  EXPECT_GT(a, 90.0);
  EXPECT_LT(a, 90.4);
}

TEST(HesaiCut, LostPacketsMakeTheirScansIncompleteAndAreCounted) {
  // XT16 (no azimuth offsets) single return: 8 firings of 0.18 deg a packet, 250 packets a turn,
  // firing f at f x 0.18 deg. Packets 300-339 are lost (mid-turn), then 490-509 (across the cut
  // at firing 4000, packet 500).
  std::set<int> skip;
  for (int k = 300; k < 340; ++k) skip.insert(k);
  for (int k = 490; k < 510; ++k) skip.insert(k);
  const Stream s = rotate(Model::kPandarXT16, 0, 18, 1000, skip);
  ASSERT_EQ(s.scans.size(), 5u);
  // Scan 0 is the firing at 0 deg; scan 1 firings 1-2000, complete; scan 2 firings 2001-4000
  // without the lost 2400-2719 and 3920-4000; scan 3 lost its head (4001-4079) and ends at 6000;
  // scan 4 is the partial tail 6001-7999.
  const std::size_t firings[5] = {1, 2000, 2000 - 320 - 81, 6000 - 4080 + 1, 7999 - 6001 + 1};
  const bool complete[5] = {false, true, false, false, false};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(s.scans[i].size(), 16u * firings[i]) << "scan " << i;
    EXPECT_EQ(s.scans[i].complete, complete[i]) << "scan " << i;
  }
  HesaiScanner scanner(Model::kPandarXT16, hesai::nominal_calibration(Model::kPandarXT16), all_returns());
  std::vector<Scan> scans;
  for (const auto& b : s.bytes) scanner.add(as_packet(b), scans);
  EXPECT_EQ(scanner.lost_packets(), 60u);
  EXPECT_THAT(scanner.describe(), HasSubstr("60 lost"));
}

TEST(HesaiCut, LossWithoutSequenceNumbersIsFoundFromTheSensorTime) {
  // Pandar40P has no UDP sequence: 10 firings of 0.2 deg a packet, 180 packets a turn.
  std::set<int> skip;
  for (int k = 100; k < 105; ++k) skip.insert(k);
  HesaiScanner scanner(Model::kPandar40P, hesai::nominal_calibration(Model::kPandar40P), all_returns());
  std::vector<Scan> scans;
  std::vector<std::vector<std::uint8_t>> keep;
  for (int k = 0; k < 400; ++k) {
    if (skip.count(k)) continue;
    Synth p =
        uniform_packet(Model::kPandar40P, 0x37, static_cast<std::uint16_t>((200 * k) % 36000), 20, 10.0);
    p.sensor_time = 1.6e9 + k * 200.0 / 100.0 / 3600.0;
    keep.push_back(p.bytes());
    scanner.add(as_packet(keep.back()), scans);
  }
  EXPECT_EQ(scanner.lost_packets(), 5u);
  // The first firing straddles the cut (offsets -5.2 to +3.1 deg): scan 0 is its channels
  // before the cut, scan 1 lost packets 100-104, scan 2 is a full turn.
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_FALSE(scans[0].complete);
  EXPECT_FALSE(scans[1].complete);
  EXPECT_TRUE(scans[2].complete);
  EXPECT_EQ(scans[2].size(), 40u * 1800u);
}

TEST(HesaiCut, GapOfARotationOrMoreEndsTheOpenScans) {
  std::set<int> skip;
  for (int k = 100; k < 400; ++k) skip.insert(k);  // 300 packets: 1.2 turns
  const Stream s = rotate(Model::kPandarXT16, 0, 18, 800, skip);
  // Scan 0: firing 0; scan 1: firings 1-799, ended by the gap; from packet 400 (216 deg) a fresh
  // start: firings 3200-4000, then 4001-6000 complete, then the tail 6001-6399.
  ASSERT_EQ(s.scans.size(), 5u);
  const std::size_t firings[5] = {1, 799, 801, 2000, 399};
  const bool complete[5] = {false, false, false, true, false};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(s.scans[i].size(), 16u * firings[i]) << "scan " << i;
    EXPECT_EQ(s.scans[i].complete, complete[i]) << "scan " << i;
  }
  EXPECT_EQ(s.scans[2].first_packet, 100u);  // index of the packet fed, not its sequence number
}

TEST(HesaiCut, ChannelCutAloneSplitsAStraddlingFirstFiring) {
  // Offsets -10 and +10 deg: block azimuth 5 deg puts channel 1 past the cut (15 deg), channel 0
  // before it (355 deg).
  ChannelCut cut({-10.0, 10.0}, 0.0);
  cut.step(500, false);
  EXPECT_EQ(cut.buffer(0), 0);
  EXPECT_EQ(cut.buffer(1), 1);
  EXPECT_TRUE(cut.split());
  ChannelCut::Step st = cut.step(900, false);
  EXPECT_EQ(st.emitted, -1);
  st = cut.step(1100, false);  // channel 0 at 1 deg: crossed
  EXPECT_EQ(st.emitted, 0);
  EXPECT_FALSE(cut.split());
  EXPECT_EQ(cut.pending(), 1);
  // Jitter backwards does not cross again.
  st = cut.step(1000, false);
  EXPECT_FALSE(st.crossed);
  EXPECT_EQ(cut.buffer(0), 1);
}

// =============================================================================================
// Sensor model

TEST(HesaiSensor, ColumnsFromTheAzimuthStepRateFromTheMotor) {
  struct Case {
    Model model;
    int step;
    int columns;
  };
  for (const Case c : {Case{Model::kPandar40P, 20, 1800}, Case{Model::kPandarXT32, 18, 2000},
                       Case{Model::kPandarQT64, 60, 600}, Case{Model::kPandarQT128, 40, 900},
                       Case{Model::kPandarXT32, 36, 1000}}) {
    auto scanner = scanner_for(c.model);
    std::vector<Scan> done;
    std::vector<std::vector<std::uint8_t>> keep;
    const int blocks = hesai::model_info(c.model).blocks;
    for (int k = 0; k < 5; ++k) {
      Synth p = uniform_packet(c.model, 0x37, static_cast<std::uint16_t>(c.step * blocks * k), c.step, 5.0);
      p.rpm = c.step == 36 ? 1200 : 599;
      p.sequence = static_cast<std::uint32_t>(k);
      keep.push_back(p.bytes());
      scanner->add(as_packet(keep.back()), done);
    }
    const SensorConfig s = scanner->sensor();
    EXPECT_EQ(s.Horizon_SCAN, c.columns) << hesai::model_name(c.model);
    EXPECT_NEAR(s.scan_rate_hz, c.step == 36 ? 20.0 : 599.0 / 60.0, 1e-12);
    EXPECT_EQ(s.preset, hesai::model_name(c.model));
    EXPECT_NO_THROW(s.validate());
  }
  // Before any packet: the model's step at 600 rpm; range: the sensor's within the configured.
  ScannerOptions o;
  o.min_range = 0.3;
  o.max_range = 300.0;
  const SensorConfig qt = scanner_for(Model::kPandarQT128, o)->sensor();
  EXPECT_EQ(qt.Horizon_SCAN, 900);
  EXPECT_DOUBLE_EQ(qt.min_range, 0.3);
  EXPECT_DOUBLE_EQ(qt.max_range, 50.0);
  EXPECT_DOUBLE_EQ(qt.scan_rate_hz, 10.0);
  EXPECT_EQ(qt.N_scan, 128);
  EXPECT_DOUBLE_EQ(qt.beam_elevations_deg.front(), qt.Pit_bottom);
}

TEST(HesaiSensor, ConfiguredRangeOutsideTheSensorsIsAnError) {
  ScannerOptions o;
  o.min_range = 60.0;  // the QT128 sees up to 50 m
  EXPECT_THAT([&] { scanner_for(Model::kPandarQT128, o); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("leaves nothing of the PandarQT128")));
  o.min_range = 5.0;
  o.max_range = 4.0;
  EXPECT_THROW(scanner_for(Model::kPandarXT32, o), InputError);
}

// =============================================================================================
// Calibration and the factory

TEST(HesaiCalibration, HeaderVariantsLineEndsAndOrder) {
  const hesai::Calibration a =
      hesai::parse_calibration("Laser id,Elevation,Azimuth\n1,2.5,-1\n2,-3,0.5\n", "a.csv");
  const hesai::Calibration b = hesai::parse_calibration(
      "\xEF\xBB\xBF"
      "Channel, Elevation, Azimuth\r\n\r\n2 , -3 , 0.5\r\n1,2.5,-1",
      "b.csv");
  const hesai::Calibration c = hesai::parse_calibration("1,2.5,-1\n2,-3,+0.5\n\n", "c.csv");
  for (const hesai::Calibration* k : {&a, &b, &c}) {
    ASSERT_EQ(k->channels(), 2);
    EXPECT_EQ(k->elevation_deg, (std::vector<double>{2.5, -3.0}));
    EXPECT_EQ(k->azimuth_deg, (std::vector<double>{-1.0, 0.5}));
  }
  EXPECT_EQ(b.source, "b.csv");
}

TEST(HesaiCalibration, BadLinesNameTheFileAndLine) {
  const auto msg = [](const std::string& text) {
    try {
      hesai::parse_calibration(text, "cal.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(msg("Channel,Elevation,Azimuth\n1,2,3\n2,x,3\n"), HasSubstr("cal.csv:3: elevation \"x\""));
  EXPECT_THAT(msg("1,2,3\n2,4\n"), HasSubstr("cal.csv:2: expected 3 fields"));
  EXPECT_THAT(msg("1,2,3\n1,4,5\n"), HasSubstr("cal.csv:2: channel 1 is defined twice (first on line 1)"));
  EXPECT_THAT(msg("1,2,3\n3,4,5\n"), HasSubstr("cal.csv: channel 2 is missing"));
  EXPECT_THAT(msg("header\n"), HasSubstr("cal.csv: no channel lines"));
  EXPECT_THAT(msg("1,2,3\n2,4,nan\n"), HasSubstr("cal.csv:2: azimuth"));
  EXPECT_THAT(msg("1,2,3\n0,4,5\n"), HasSubstr("cal.csv:2: channel id \"0\""));
  EXPECT_THAT(msg("1,2,3\nChannel,Elevation,Azimuth\n"), HasSubstr("cal.csv:2: channel id \"Channel\""));
}

TEST(HesaiCalibration, SharedCsvsAreTheBuiltInTables) {
  const std::string dir = kHesai + "/calibration";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is absent";
  for (const Model m : hesai::all_models()) {
    const hesai::Calibration file = hesai::read_calibration(dir + "/" + hesai::model_name(m) + ".csv");
    const hesai::Calibration nominal = hesai::nominal_calibration(m);
    EXPECT_EQ(file.elevation_deg, nominal.elevation_deg) << hesai::model_name(m);
    EXPECT_EQ(file.azimuth_deg, nominal.azimuth_deg) << hesai::model_name(m);
    EXPECT_NO_THROW(hesai::check_calibration(file, m));
  }
}

TEST(HesaiCalibration, TableOfAnotherModelIsRejected) {
  // Same channel count, other model: XT32M's table for an XT32, QT64's for a Pandar64.
  EXPECT_THAT(
      [] { hesai::check_calibration(hesai::nominal_calibration(Model::kPandarXT32M), Model::kPandarXT32); },
      ::testing::ThrowsMessage<InputError>(AllOf(HasSubstr("built-in PandarXT32M table"),
                                                 HasSubstr("not a PandarXT32 angle-correction table"))));
  EXPECT_THROW(hesai::check_calibration(hesai::nominal_calibration(Model::kPandarQT64), Model::kPandar64),
               InputError);
  EXPECT_THROW(hesai::check_calibration(hesai::nominal_calibration(Model::kPandar64), Model::kPandarQT64),
               InputError);
  EXPECT_THROW(hesai::check_calibration(hesai::nominal_calibration(Model::kPandarXT32), Model::kPandarXT32M),
               InputError);
  // Another channel count.
  EXPECT_THAT(
      [] { hesai::check_calibration(hesai::nominal_calibration(Model::kPandarXT16), Model::kPandarXT32); },
      ::testing::ThrowsMessage<InputError>(HasSubstr("16 channels, but a PandarXT32 has 32")));
}

TEST(HesaiFactory, ModelFromThePacketsOrTheOptions) {
  const std::vector<std::uint8_t> xt = uniform_packet(Model::kPandarXT32M, 0x3c, 0, 18, 5.0).bytes();
  std::vector<std::uint8_t> gps(512, 0);
  gps[0] = 0xFF, gps[1] = 0xEE;
  DriverOptions o;
  auto s = make_hesai_scanner(o, {as_packet(gps), as_packet(xt)}, HesaiOptions{});
  EXPECT_EQ(s->model(), Model::kPandarXT32M);
  EXPECT_THAT(s->describe(), HasSubstr("built-in PandarXT32M table"));
  o.model = "XT32M2X";
  EXPECT_EQ(make_hesai_scanner(o, {}, HesaiOptions{})->model(), Model::kPandarXT32M);
  o.model = "pandar-qt128";
  EXPECT_EQ(make_hesai_scanner(o, {}, HesaiOptions{})->model(), Model::kPandarQT128);
  o.model = "PandarXT32";
  EXPECT_THAT(
      [&] { make_hesai_scanner(o, {as_packet(xt, 0.0, "bag: packet 0")}); },
      ::testing::ThrowsMessage<InputError>(AllOf(HasSubstr("bag: packet 0"), HasSubstr("PandarXT32M"))));
  o.model = "Pandar128";
  EXPECT_THAT([&] { make_hesai_scanner(o, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("unknown Hesai model")));
  o.model.clear();
  EXPECT_THAT([&] { make_hesai_scanner(o, {as_packet(gps)}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("no Hesai data packet")));
}

TEST(HesaiFactory, SharedCsvOfAnotherModelThanThePackets) {
  const std::string csv = kHesai + "/calibration/PandarXT32M.csv";
  if (!std::filesystem::exists(csv)) GTEST_SKIP() << csv << " is absent";
  const std::vector<std::uint8_t> xt32 = uniform_packet(Model::kPandarXT32, 0x39, 0, 18, 5.0).bytes();
  DriverOptions o;
  o.calibration = csv;
  EXPECT_THAT([&] { make_hesai_scanner(o, {as_packet(xt32)}); },
              ::testing::ThrowsMessage<InputError>(
                  AllOf(HasSubstr(csv), HasSubstr("not a PandarXT32 angle-correction table"))));
}

TEST(HesaiFactory, CalibrationFileOfTheWrongSizeOrModel) {
  std::string csv = "Laser id,Elevation,Azimuth\n";
  for (int c = 1; c <= 16; ++c) csv += std::to_string(c) + "," + std::to_string(15 - 2 * (c - 1)) + ",0\n";
  const std::string path = temp_file("dloam_hesai_16.csv", csv);
  DriverOptions o;
  o.model = "PandarXT16";
  o.calibration = path;
  EXPECT_EQ(make_hesai_scanner(o, {}, HesaiOptions{})->calibration().channels(), 16);
  o.model = "PandarXT32";
  EXPECT_THAT([&] { make_hesai_scanner(o, {}); },
              ::testing::ThrowsMessage<InputError>(AllOf(HasSubstr(path), HasSubstr("16 channels"))));
  o.calibration = path + ".missing";
  EXPECT_THAT([&] { make_hesai_scanner(o, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("cannot open")));
  std::filesystem::remove(path);
}

// =============================================================================================
// nebula's reference clouds

namespace {
struct Reference {
  std::string folder;  // under hesai/nebula
  Model model;
  double min_range, max_range;           // nebula's test configuration
  std::vector<std::size_t> per_message;  // points of the scan nebula emits in each message (README)
};

void check_reference(const Reference& r) {
  const std::string dir = kHesai + "/" + r.folder;
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is absent";
  std::string pcd;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".pcd") pcd = e.path().string();
  ASSERT_FALSE(pcd.empty());
  const Bag bag = read_pandar_bag(bag_folder(dir));
  const std::int64_t reference_message = std::stoll(std::filesystem::path(pcd).stem().string());
  DriverOptions o;
  o.calibration = kHesai + "/calibration/" + hesai::model_name(r.model) + ".csv";
  o.scan.returns = ReturnMode::kAll;
  o.scan.cut_azimuth_deg = 0.0;
  o.scan.min_range = r.min_range;
  o.scan.max_range = r.max_range;
  std::vector<Packet> first;
  for (std::size_t i = 0; i < std::min<std::size_t>(bag.packets.size(), 10); ++i)
    first.push_back(as_packet(bag.packets[i].bytes, bag.packets[i].stamp));
  auto scanner = make_hesai_scanner(o, first, HesaiOptions{});
  ASSERT_EQ(scanner->model(), r.model);
  std::vector<Scan> during;  // scans completed while the reference message was decoded
  std::vector<Scan> done;
  std::vector<std::size_t> per_message(bag.timestamps.size(), 0);
  for (const BagPacket& p : bag.packets) {
    done.clear();
    scanner->add(
        as_packet(p.bytes, p.stamp,
                  r.folder + ": message " + std::to_string(p.message) + " packet " + std::to_string(p.index)),
        done);
    for (const Scan& s : done) per_message[p.message] += s.size();
    if (bag.timestamps[p.message] == reference_message)
      for (Scan& s : done) during.push_back(std::move(s));
  }
  // Every scan, not only the reference one, has nebula's point count.
  EXPECT_EQ(per_message, r.per_message);
  ASSERT_EQ(during.size(), 1u) << "scans completed during the reference message";
  const Scan& scan = during[0];
  const PointCloud ref = io::read_pcd(pcd);
  ASSERT_EQ(scan.size(), ref.size());
  // nebula's frame is Hesai's (x right, y front); dloam's is x front, y left: (y, -x, z).
  double worst = 0.0;
  std::size_t worst_index = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const Vec3& n = ref.xyz[i];
    const double e = (scan.xyz[i] - Vec3(n.y(), -n.x(), n.z())).cwiseAbs().maxCoeff();
    if (e > worst) worst = e, worst_index = i;
  }
  EXPECT_LT(worst, 1e-3) << "point " << worst_index;
  ::testing::Test::RecordProperty("max_abs_coordinate_difference_m", std::to_string(worst));
  std::printf("%s: %zu points, largest coordinate difference %.3g m, %s\n", r.folder.c_str(), scan.size(),
              worst, scanner->describe().c_str());
}
}  // namespace

// The configurations of nebula's test, and the scans it emits per message (sensors README).
TEST(HesaiReference, Pandar40P) {
  check_reference({"40p", Model::kPandar40P, 0.3, 200.0, {152, 56530, 56723, 56762}});
}
TEST(HesaiReference, Pandar64) {
  check_reference({"64", Model::kPandar64, 0.3, 200.0, {244, 93079, 93672, 93591}});
}
TEST(HesaiReference, PandarQT64) {
  check_reference({"qt64", Model::kPandarQT64, 0.1, 60.0, {259, 33940, 34145, 34158}});
}
TEST(HesaiReference, PandarQT128) {
  check_reference({"qt128", Model::kPandarQT128, 0.3, 300.0, {71559, 73560}});
}
TEST(HesaiReference, PandarXT16) {
  check_reference({"xt16", Model::kPandarXT16, 0.05, 120.0, {7905, 26299, 26287, 26252}});
}
TEST(HesaiReference, PandarXT32) {
  check_reference({"xt32", Model::kPandarXT32, 0.05, 120.0, {62826, 63058, 63040, 63021}});
}
TEST(HesaiReference, PandarXT32M) {
  check_reference({"xt32m", Model::kPandarXT32M, 0.5, 300.0, {48009, 12176, 43227, 13574}});
}

TEST(HesaiReference, Xt32mLostPacketsAreCountedAndItsScansIncomplete) {
  const std::string dir = kHesai + "/xt32m";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is absent";
  const Bag bag = read_pandar_bag(bag_folder(dir));
  HesaiScanner scanner(Model::kPandarXT32M, hesai::nominal_calibration(Model::kPandarXT32M), all_returns());
  std::vector<Scan> done;
  for (const BagPacket& p : bag.packets) scanner.add(as_packet(p.bytes, p.stamp), done);
  EXPECT_EQ(scanner.lost_packets(), 852u);  // udp_sequence gaps of 413, 44 and 395
  EXPECT_EQ(scanner.packets(), bag.packets.size());
  for (const Scan& s : done)
    EXPECT_FALSE(s.complete) << "scan of packets " << s.first_packet << "-" << s.last_packet;
}
