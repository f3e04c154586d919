// Helpers of the capture tests: hand-made pcap / pcapng files with Ethernet (optionally VLAN
// tagged), Linux cooked or raw-IP frames carrying IPv4 / UDP datagrams, whole or fragmented.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dloam::test {

using Bytes = std::vector<std::uint8_t>;

inline void put_le32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
inline void put_le16(Bytes& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}
inline void put_be16(Bytes& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}
inline void put_be32(Bytes& b, std::uint32_t v) {
  put_be16(b, static_cast<std::uint16_t>(v >> 16));
  put_be16(b, static_cast<std::uint16_t>(v));
}

/// A payload whose bytes tell where they came from: byte i = (seed + i) mod 251.
inline Bytes payload(std::size_t n, unsigned seed) {
  Bytes p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>((seed + i) % 251);
  return p;
}

/// UDP header + payload; `udp_length` 0 = the true length.
inline Bytes udp(std::uint16_t src_port, std::uint16_t dst_port, const Bytes& data,
                 std::uint16_t udp_length = 0) {
  Bytes b;
  put_be16(b, src_port);
  put_be16(b, dst_port);
  put_be16(b, udp_length ? udp_length : static_cast<std::uint16_t>(8 + data.size()));
  put_be16(b, 0);  // no checksum
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

/// IPv4 header (no options) + `body`. `total_length` 0 = the true length.
inline Bytes ipv4(const Bytes& body, std::uint16_t id = 1, std::size_t fragment_offset = 0, bool more = false,
                  std::uint8_t protocol = 17, std::uint16_t total_length = 0) {
  Bytes b;
  b.push_back(0x45);
  b.push_back(0);
  put_be16(b, total_length ? total_length : static_cast<std::uint16_t>(20 + body.size()));
  put_be16(b, id);
  put_be16(b, static_cast<std::uint16_t>((more ? 0x2000 : 0) | (fragment_offset / 8)));
  b.push_back(64);
  b.push_back(protocol);
  put_be16(b, 0);
  put_be32(b, 0xC0A801C9);  // 192.168.1.201
  put_be32(b, 0xC0A80164);  // 192.168.1.100
  b.insert(b.end(), body.begin(), body.end());
  return b;
}

/// The fragments of one UDP datagram, `chunk` IP-payload bytes each (a multiple of 8).
inline std::vector<Bytes> fragments(const Bytes& udp_datagram, std::size_t chunk, std::uint16_t id) {
  std::vector<Bytes> out;
  for (std::size_t at = 0; at < udp_datagram.size(); at += chunk) {
    const std::size_t n = std::min(chunk, udp_datagram.size() - at);
    Bytes part(udp_datagram.begin() + static_cast<long>(at),
               udp_datagram.begin() + static_cast<long>(at + n));
    out.push_back(ipv4(part, id, at, at + n < udp_datagram.size()));
  }
  return out;
}

/// Ethernet II frame with optional 802.1Q tags.
inline Bytes ethernet(const Bytes& ip, int vlan_tags = 0, std::uint16_t ethertype = 0x0800) {
  Bytes b(12, 0xAA);
  for (int t = 0; t < vlan_tags; ++t) {
    put_be16(b, t == 0 && vlan_tags > 1 ? 0x88A8 : 0x8100);
    put_be16(b, static_cast<std::uint16_t>(100 + t));
  }
  put_be16(b, ethertype);
  b.insert(b.end(), ip.begin(), ip.end());
  return b;
}

/// Linux cooked (SLL) frame.
inline Bytes linux_cooked(const Bytes& ip) {
  Bytes b;
  put_be16(b, 0);  // packet type: to us
  put_be16(b, 1);  // ARPHRD_ETHER
  put_be16(b, 6);
  for (int i = 0; i < 8; ++i) b.push_back(0x11);
  put_be16(b, 0x0800);
  b.insert(b.end(), ip.begin(), ip.end());
  return b;
}

struct Record {
  double time;
  Bytes frame;
  std::size_t wire_length = 0;  ///< 0 = the frame's size
};

/// A classic pcap file (little-endian; µs or ns timestamps).
inline Bytes pcap_file(int linktype, const std::vector<Record>& records, bool nanoseconds = false) {
  Bytes b;
  put_le32(b, nanoseconds ? 0xA1B23C4D : 0xA1B2C3D4);
  put_le16(b, 2);
  put_le16(b, 4);
  put_le32(b, 0);
  put_le32(b, 0);
  put_le32(b, 65535);
  put_le32(b, static_cast<std::uint32_t>(linktype));
  for (const auto& r : records) {
    const auto sec = static_cast<std::uint32_t>(r.time);
    const double frac = r.time - sec;
    put_le32(b, sec);
    put_le32(b, static_cast<std::uint32_t>(frac * (nanoseconds ? 1e9 : 1e6) + 0.5));
    put_le32(b, static_cast<std::uint32_t>(r.frame.size()));
    put_le32(b, static_cast<std::uint32_t>(r.wire_length ? r.wire_length : r.frame.size()));
    b.insert(b.end(), r.frame.begin(), r.frame.end());
  }
  return b;
}

/// A pcapng file: section header, one Ethernet interface (ns timestamps), enhanced packet blocks.
inline Bytes pcapng_file(const std::vector<Record>& records) {
  Bytes b;
  auto block = [&](std::uint32_t type, const Bytes& body) {
    Bytes padded = body;
    while (padded.size() % 4) padded.push_back(0);
    const auto len = static_cast<std::uint32_t>(12 + padded.size());
    put_le32(b, type);
    put_le32(b, len);
    b.insert(b.end(), padded.begin(), padded.end());
    put_le32(b, len);
  };
  Bytes shb;
  put_le32(shb, 0x1A2B3C4D);
  put_le16(shb, 1);
  put_le16(shb, 0);
  put_le32(shb, 0xFFFFFFFF);
  put_le32(shb, 0xFFFFFFFF);
  block(0x0A0D0D0A, shb);
  Bytes idb;
  put_le16(idb, 1);  // Ethernet
  put_le16(idb, 0);
  put_le32(idb, 0);  // no snaplen limit
  put_le16(idb, 9);  // if_tsresol
  put_le16(idb, 1);
  idb.push_back(9);  // 10^-9 s
  idb.push_back(0);
  idb.push_back(0);
  idb.push_back(0);
  put_le16(idb, 0);  // opt_endofopt
  put_le16(idb, 0);
  block(1, idb);
  for (const auto& r : records) {
    const auto ns = static_cast<std::uint64_t>(r.time * 1e9 + 0.5);
    Bytes epb;
    put_le32(epb, 0);
    put_le32(epb, static_cast<std::uint32_t>(ns >> 32));
    put_le32(epb, static_cast<std::uint32_t>(ns));
    put_le32(epb, static_cast<std::uint32_t>(r.frame.size()));
    put_le32(epb, static_cast<std::uint32_t>(r.frame.size()));
    epb.insert(epb.end(), r.frame.begin(), r.frame.end());
    block(6, epb);
  }
  return b;
}

}  // namespace dloam::test
