// Helpers of the Velodyne decoder tests: synthetic data packets, the recordings of the sensors
// folder as packets, binary PCD references.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dloam/drivers/velodyne.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/pcap.hpp"

namespace dloam::test {

/// A 1206-byte data packet built field by field.
struct VelodynePacketBuilder {
  std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(1206, 0);

  VelodynePacketBuilder& block(int b, std::uint16_t flag, std::uint16_t azimuth) {
    put16(b * 100, flag);
    put16(b * 100 + 2, azimuth);
    return *this;
  }
  /// Every block: flag, and azimuth start + b * step (0.01 deg).
  VelodynePacketBuilder& blocks(std::uint16_t flag, int start, int step) {
    for (int b = 0; b < 12; ++b) block(b, flag, static_cast<std::uint16_t>((start + b * step) % 36000));
    return *this;
  }
  VelodynePacketBuilder& ret(int b, int channel, std::uint16_t raw, std::uint8_t reflectivity) {
    put16(b * 100 + 4 + 3 * channel, raw);
    bytes[static_cast<std::size_t>(b * 100 + 6 + 3 * channel)] = reflectivity;
    return *this;
  }
  VelodynePacketBuilder& toh(std::uint32_t us) {
    for (int i = 0; i < 4; ++i)
      bytes[static_cast<std::size_t>(1200 + i)] = static_cast<std::uint8_t>(us >> (8 * i));
    return *this;
  }
  VelodynePacketBuilder& mode(std::uint8_t m) {
    bytes[1204] = m;
    return *this;
  }
  VelodynePacketBuilder& product(std::uint8_t p) {
    bytes[1205] = p;
    return *this;
  }
  void put16(int at, std::uint16_t v) {
    bytes[static_cast<std::size_t>(at)] = static_cast<std::uint8_t>(v);
    bytes[static_cast<std::size_t>(at + 1)] = static_cast<std::uint8_t>(v >> 8);
  }
};

/// Packets that own their bytes.
struct Recording {
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<double> stamps;
  std::vector<std::uint16_t> ports;
  std::vector<std::string> where;
  std::vector<int> message;  ///< bag message of each packet (-1 in a pcap)
  std::vector<std::int64_t> message_time_ns;

  [[nodiscard]] std::size_t size() const { return bytes.size(); }
  [[nodiscard]] drivers::Packet packet(std::size_t i) const {
    drivers::Packet p;
    p.data = bytes[i].data();
    p.size = bytes[i].size();
    p.stamp = stamps[i];
    p.port = ports[i];
    p.where = where[i];
    return p;
  }
  [[nodiscard]] std::vector<drivers::Packet> first(std::size_t n) const {
    std::vector<drivers::Packet> out;
    for (std::size_t i = 0; i < n && i < size(); ++i) out.push_back(packet(i));
    return out;
  }
};

inline Recording read_pcap(const std::string& path) {
  Recording r;
  io::PcapReader reader(path);
  io::UdpDatagram d;
  while (reader.next(d)) {
    r.bytes.push_back(d.payload);
    r.stamps.push_back(d.time);
    r.ports.push_back(d.dst_port);
    r.where.push_back(path + ": datagram " + std::to_string(d.index));
    r.message.push_back(-1);
  }
  return r;
}

/// Every packet of the bag's only topic, in message order.
inline Recording read_bag(const std::string& folder) {
  Recording r;
  io::Bag bag(folder);
  const io::BagTopic& topic = bag.topics().at(0);
  for (std::size_t k = 0; k < bag.message_count(topic.name); ++k) {
    const std::vector<std::uint8_t> data = bag.read(topic.name, k);
    const std::int64_t t = bag.message_time_ns(topic.name, k);
    r.message_time_ns.push_back(t);
    const io::PacketMessage m = io::decode_packet_message(
        topic.type, data.data(), data.size(), 1e-9 * static_cast<double>(t), bag.where(topic.name, k));
    for (std::size_t i = 0; i < m.packets.size(); ++i) {
      const io::PacketSlice& s = m.packets[i];
      r.bytes.emplace_back(data.begin() + static_cast<std::ptrdiff_t>(s.offset),
                           data.begin() + static_cast<std::ptrdiff_t>(s.offset + s.size));
      r.stamps.push_back(s.stamp);
      r.ports.push_back(0);
      r.where.push_back(bag.where(topic.name, k) + ", packet " + std::to_string(i));
      r.message.push_back(static_cast<int>(k));
    }
  }
  return r;
}

/// A binary PCD file: one column of doubles per field.
struct Pcd {
  std::vector<std::string> fields;
  std::vector<std::vector<double>> columns;
  std::size_t points = 0;

  [[nodiscard]] const std::vector<double>& column(const std::string& name) const {
    for (std::size_t k = 0; k < fields.size(); ++k)
      if (fields[k] == name) return columns[k];
    throw std::runtime_error("no field " + name);
  }
  [[nodiscard]] Vec3 xyz(std::size_t i) const { return Vec3(columns[0][i], columns[1][i], columns[2][i]); }
};

inline Pcd read_binary_pcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  Pcd p;
  std::vector<int> sizes;
  std::vector<char> types;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "FIELDS") {
      for (std::string f; s >> f;) p.fields.push_back(f);
    } else if (key == "SIZE") {
      for (int v; s >> v;) sizes.push_back(v);
    } else if (key == "TYPE") {
      for (char c; s >> c;) types.push_back(c);
    } else if (key == "POINTS") {
      s >> p.points;
    } else if (key == "DATA") {
      std::string kind;
      s >> kind;
      if (kind != "binary") throw std::runtime_error(path + ": not a binary PCD");
      break;
    }
  }
  std::size_t record = 0;
  for (int v : sizes) record += static_cast<std::size_t>(v);
  p.columns.assign(p.fields.size(), std::vector<double>(p.points));
  std::vector<std::uint8_t> buf(record);
  for (std::size_t i = 0; i < p.points; ++i) {
    in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(record));
    if (!in) throw std::runtime_error(path + ": data shorter than POINTS");
    std::size_t o = 0;
    for (std::size_t k = 0; k < p.fields.size(); ++k) {
      const int sz = sizes[k];
      double v = 0;
      if (types[k] == 'F' && sz == 4) {
        float f;
        std::memcpy(&f, &buf[o], 4);
        v = f;
      } else if (types[k] == 'U' && sz == 1) {
        v = buf[o];
      } else if (types[k] == 'U' && sz == 2) {
        std::uint16_t u;
        std::memcpy(&u, &buf[o], 2);
        v = u;
      } else if (types[k] == 'U' && sz == 4) {
        std::uint32_t u;
        std::memcpy(&u, &buf[o], 4);
        v = u;
      } else {
        throw std::runtime_error(path + ": unexpected field type");
      }
      p.columns[k][i] = v;
      o += static_cast<std::size_t>(sz);
    }
  }
  return p;
}

}  // namespace dloam::test
