// Hesai data-packet layouts: identification, validation and field access.
#include "dloam/drivers/hesai_packet.hpp"

#include <array>
#include <cstdio>

#include "dloam/core/types.hpp"

namespace dloam::drivers::hesai {

namespace {

constexpr std::size_t k40PSize = 1262;
constexpr std::size_t kGpsSize = 512;

[[noreturn]] void fail(const Packet& packet, const std::string& what) {
  throw InputError((packet.where.empty() ? std::string("Hesai packet") : packet.where) + ": " + what);
}

std::string hex2(unsigned v) {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "%02x", v & 0xFFu);
  return buf;
}

std::uint16_t u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// Days from 1970-01-01 to a proleptic Gregorian date (H. Hinnant's civil-from-days inverse).
long long days_from_civil(long long y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

// Date (year byte + base, month, day, hour, minute, second) and microseconds -> seconds since 1970.
double packet_time(const std::uint8_t* date, int year_base, std::uint32_t micros) {
  const unsigned month = date[1] >= 1 && date[1] <= 12 ? date[1] : 1;
  const unsigned day = date[2] >= 1 && date[2] <= 31 ? date[2] : 1;
  const long long days = days_from_civil(year_base + date[0], month, day);
  const long long seconds = days * 86400 + date[3] * 3600LL + date[4] * 60LL + date[5];
  return static_cast<double>(seconds) + micros * 1e-6;
}

// Slicing-by-16 tables of CRC-32/MPEG-2: tables[0] is the byte-wise table, tables[k] advances a
// byte's remainder by k more zero bytes.
using CrcTables = std::array<std::array<std::uint32_t, 256>, 16>;
const CrcTables& crc_tables() {
  static const CrcTables tables = [] {
    CrcTables t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i << 24;
      for (int k = 0; k < 8; ++k) c = (c & 0x80000000u) ? (c << 1) ^ 0x04C11DB7u : c << 1;
      t[0][i] = c;
    }
    for (std::size_t k = 1; k < 16; ++k)
      for (std::size_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] << 8) ^ t[0][t[k - 1][i] >> 24];
    return t;
  }();
  return tables;
}

void expect_size(const Packet& packet, Model model, std::size_t expected, const std::string& why) {
  if (packet.size != expected)
    fail(packet, std::string(model_name(model)) + " packet of " + std::to_string(packet.size) +
                     " bytes; its header" + why + " gives " + std::to_string(expected));
}

}  // namespace

std::uint32_t crc32_mpeg2(const std::uint8_t* data, std::size_t size) {
  const CrcTables& t = crc_tables();
  std::uint32_t crc = 0xFFFFFFFFu;
  std::size_t i = 0;
  for (; i + 16 <= size; i += 16) {
    const std::uint8_t* p = data + i;
    crc ^= (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
           (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
    crc = t[15][crc >> 24] ^ t[14][(crc >> 16) & 0xFFu] ^ t[13][(crc >> 8) & 0xFFu] ^ t[12][crc & 0xFFu] ^
          t[11][p[4]] ^ t[10][p[5]] ^ t[9][p[6]] ^ t[8][p[7]] ^ t[7][p[8]] ^ t[6][p[9]] ^ t[5][p[10]] ^
          t[4][p[11]] ^ t[3][p[12]] ^ t[2][p[13]] ^ t[1][p[14]] ^ t[0][p[15]];
  }
  for (; i < size; ++i) crc = (crc << 8) ^ t[0][((crc >> 24) ^ data[i]) & 0xFFu];
  return crc;
}

bool is_gps_packet(const Packet& packet) {
  return packet.size == kGpsSize && packet.data != nullptr && packet.data[0] == 0xFF &&
         packet.data[1] == 0xEE;
}

bool looks_like_data_packet(const Packet& packet) {
  if (packet.data == nullptr || packet.size < 12) return false;
  const std::uint8_t* d = packet.data;
  if (d[0] == 0xEE && d[1] == 0xFF) return true;
  if (packet.size != k40PSize || d[0] != 0xFF || d[1] != 0xEE) return false;
  return d[124] == 0xFF && d[125] == 0xEE && d[1116] == 0xFF && d[1117] == 0xEE;
}

Model identify_model(const Packet& packet) {
  if (packet.data == nullptr || packet.size < 12)
    fail(packet, std::to_string(packet.size) + " bytes: too short for a Hesai data packet");
  const std::uint8_t* d = packet.data;
  if (d[0] == 0xFF && d[1] == 0xEE) {
    if (packet.size == k40PSize) return Model::kPandar40P;
    if (packet.size == kGpsSize) fail(packet, "a Hesai GPS packet, not a point-cloud data packet");
    fail(packet, "starts with the block marker FF EE of a header-less Pandar40P packet but has " +
                     std::to_string(packet.size) + " bytes, not " + std::to_string(k40PSize));
  }
  if (d[0] != 0xEE || d[1] != 0xFF)
    fail(packet, "not a Hesai data packet: starts " + hex2(d[0]) + " " + hex2(d[1]) + ", not EE FF");
  if (d[2] == 64 && d[3] == 6) return Model::kPandar64;  // 8-byte header: 64 lasers, 6 blocks
  const int major = d[2], minor = d[3];
  const int lasers = d[6], blocks = d[7];
  const std::string version = std::to_string(major) + "." + std::to_string(minor);
  if (major == 3 && minor == 1) return Model::kPandarQT64;
  if (major == 3 && minor == 2) return Model::kPandarQT128;
  if (major == 6 && minor == 1) {
    if (lasers == 16 && blocks == 8) return Model::kPandarXT16;
    if (lasers == 32 && blocks == 8) return Model::kPandarXT32;
    if (lasers == 32 && blocks == 6) return Model::kPandarXT32M;
    fail(packet, "protocol 6.1 (PandarXT family) with " + std::to_string(lasers) + " lasers and " +
                     std::to_string(blocks) + " blocks is not a known PandarXT model");
  }
  std::string family;
  if (major == 1) family = " (Pandar128 / OT128 family)";
  if (major == 4) family = " (AT128 family)";
  fail(packet,
       "Hesai protocol version " + version + family + " is not supported; supported: " + model_list());
}

PacketView parse_packet(const Packet& packet, Model model) {
  const Model seen = identify_model(packet);
  if (seen != model)
    fail(packet, std::string("a ") + model_name(seen) + " packet in a " + model_name(model) + " stream");
  const ModelInfo& info = model_info(model);
  const std::uint8_t* d = packet.data;
  PacketView v;
  v.model = model;
  v.data = d;
  v.size = packet.size;
  v.blocks = info.blocks;
  v.channels = info.channels;
  const std::uint8_t* tail = nullptr;
  const std::uint8_t* date = nullptr;
  std::uint32_t micros = 0;
  int year_base = 1900;
  switch (model) {
    case Model::kPandar40P: {
      v.unit_size = 3;
      v.block_stride = 2 + 2 + 40 * 3;
      v.block_offset = 2;
      for (int b = 0; b < v.blocks; ++b) {
        const std::uint8_t* blk = d + v.block_stride * static_cast<std::size_t>(b);
        if (blk[0] != 0xFF || blk[1] != 0xEE)
          fail(packet, "Pandar40P block " + std::to_string(b) + " starts " + hex2(blk[0]) + " " +
                           hex2(blk[1]) + ", not the block marker FF EE");
      }
      tail = d + v.block_stride * 10;
      v.dis_unit_mm = 4;
      v.motor_rpm = u16(tail + 8);
      micros = u32(tail + 10);
      v.return_mode = tail[14];
      date = tail + 16;
      year_base = 2000;
      break;
    }
    case Model::kPandar64: {
      v.unit_size = 3;
      v.block_stride = 2 + 64 * 3;
      v.block_offset = 8;
      const std::size_t body_end = 8 + v.block_stride * 6;
      if (packet.size != body_end + 22 && packet.size != body_end + 26)
        fail(packet, "Pandar64 packet of " + std::to_string(packet.size) + " bytes; its header gives " +
                         std::to_string(body_end + 22) + " or, with a UDP sequence, " +
                         std::to_string(body_end + 26));
      tail = d + body_end;
      v.dis_unit_mm = d[5];
      v.motor_rpm = u16(tail + 8);
      micros = u32(tail + 10);
      v.return_mode = tail[14];
      date = tail + 16;
      if (packet.size == body_end + 26) {
        v.has_sequence = true;
        v.sequence = u32(tail + 22);
      }
      break;
    }
    default: {  // 12-byte header
      const int lasers = d[6], blocks = d[7];
      if (lasers != info.channels || blocks != info.blocks)
        fail(packet, std::string(info.name) + " header says " + std::to_string(lasers) + " lasers and " +
                         std::to_string(blocks) + " blocks, not " + std::to_string(info.channels) + " and " +
                         std::to_string(info.blocks));
      v.unit_size = 4;
      v.block_stride = 2 + static_cast<std::size_t>(lasers) * 4;
      v.block_offset = 12;
      v.dis_unit_mm = d[9];
      const std::uint8_t flags = d[11];
      const bool sequence_flag = (flags & 0x01) != 0;
      const std::size_t body_end = 12 + v.block_stride * static_cast<std::size_t>(blocks);
      if (model == Model::kPandarQT64) {
        expect_size(packet, model, body_end + 24 + (sequence_flag ? 4 : 0),
                    sequence_flag ? " (with UDP sequence)" : " (without UDP sequence)");
        tail = d + body_end;
        v.motor_rpm = u16(tail + 10);
        micros = u32(tail + 12);
        v.return_mode = tail[16];
        date = tail + 18;
        if (sequence_flag) {
          v.has_sequence = true;
          v.sequence = u32(tail + 24);
        }
      } else if (model == Model::kPandarQT128) {
        const bool safety = (flags & 0x04) != 0, signature = (flags & 0x08) != 0;
        if (flags & 0x02)
          fail(packet, "PandarQT128 packet with IMU data (header flag bit 1) is not supported");
        const std::size_t tail_at = body_end + 4 + (safety ? 17 : 0);
        expect_size(packet, model, tail_at + 34 + (signature ? 32 : 0),
                    std::string(" (functional safety ") + (safety ? "on" : "off") + ", signature " +
                        (signature ? "on" : "off") + ")");
        tail = d + tail_at;
        v.mode_flag = tail[5];
        v.return_mode = tail[12];
        v.motor_rpm = u16(tail + 13);
        date = tail + 15;
        micros = u32(tail + 21);
        v.has_sequence = true;
        v.sequence = u32(tail + 26);
        v.crc_checked = true;
        v.crc_ok = crc32_mpeg2(d + 12, body_end - 12) == u32(d + body_end) &&
                   crc32_mpeg2(tail, 30) == u32(tail + 30);
      } else {  // XT family
        expect_size(packet, model, body_end + 24 + (sequence_flag ? 4 : 0),
                    sequence_flag ? " (with UDP sequence)" : " (without UDP sequence)");
        tail = d + body_end;
        v.return_mode = tail[10];
        v.motor_rpm = u16(tail + 11);
        date = tail + 13;
        micros = u32(tail + 19);
        if (sequence_flag) {
          v.has_sequence = true;
          v.sequence = u32(tail + 24);
        }
      }
      break;
    }
  }
  if (v.dis_unit_mm == 0) fail(packet, "distance unit 0 mm in the header");
  v.dis_unit_m = v.dis_unit_mm / 1000.0;
  v.layout = return_layout(model, v.return_mode);
  if (v.layout.returns == 0) fail(packet, "unknown return mode 0x" + hex2(v.return_mode));
  if (v.blocks % v.layout.returns != 0)
    fail(packet, std::to_string(v.blocks) + " blocks do not divide into " + v.layout.name + " groups");
  for (int b = 0; b < v.blocks; ++b)
    if (v.azimuth(b) >= 36000)
      fail(packet, "block " + std::to_string(b) + " azimuth " + std::to_string(v.azimuth(b)) +
                       " (0.01 deg) is not below 360 deg");
  v.sensor_time = packet_time(date, year_base, micros);
  return v;
}

}  // namespace dloam::drivers::hesai
