// Test helpers for the Ouster decoder: MD5 (nettle), the UDP datagrams of a capture, and a
// builder of synthetic lidar packets for any supported profile.
#pragma once

#include <nettle/md5.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dloam/drivers/ouster.hpp"
#include "dloam/io/pcap.hpp"

namespace ouster_test {

using namespace dloam::drivers;

/// Incremental MD5, hex digest.
class Md5 {
 public:
  Md5() { md5_init(&ctx_); }
  void update(const void* data, std::size_t size) {
    md5_update(&ctx_, size, static_cast<const std::uint8_t*>(data));
  }
  template <typename T>
  void update(const std::vector<T>& v) {
    update(v.data(), v.size() * sizeof(T));
  }
  std::string hex() {
    std::uint8_t d[MD5_DIGEST_SIZE];
    md5_digest(&ctx_, MD5_DIGEST_SIZE, d);
    static const char* kHex = "0123456789abcdef";
    std::string s;
    for (const std::uint8_t b : d) {
      s += kHex[b >> 4];
      s += kHex[b & 15];
    }
    return s;
  }

 private:
  md5_ctx ctx_{};
};

struct UdpRecord {
  double stamp = 0.0;
  std::uint16_t port = 0;
  std::vector<std::uint8_t> payload;
};

/// Every UDP datagram of a capture (dloam::io::PcapReader).
inline std::vector<UdpRecord> read_udp_pcap(const std::string& path) {
  dloam::io::PcapReader reader(path);
  std::vector<UdpRecord> out;
  dloam::io::UdpDatagram d;
  while (reader.next(d)) {
    UdpRecord r;
    r.stamp = d.time;
    r.port = d.dst_port;
    r.payload = d.payload;
    out.push_back(std::move(r));
  }
  return out;
}

/// Packets over records, named "<name>: packet <i>".
inline std::vector<Packet> packets_of(const std::vector<UdpRecord>& recs, const std::string& name) {
  std::vector<Packet> out;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    Packet p;
    p.data = recs[i].payload.data();
    p.size = recs[i].payload.size();
    p.stamp = recs[i].stamp;
    p.port = recs[i].port;
    p.where = name + ": packet " + std::to_string(i);
    out.push_back(p);
  }
  return out;
}

/// Writes `value` (before upshift) into a pixel at the field's bit position.
inline void put_field(std::uint8_t* px, const OusterFieldLayout& f, std::uint32_t value) {
  const std::uint64_t v = static_cast<std::uint64_t>(value >> f.upshift) &
                          ((f.bits >= 32) ? 0xFFFFFFFFull : ((1ull << f.bits) - 1));
  for (int b = 0; b < f.bits; ++b) {
    const int bit = f.bit_start + b;
    if ((v >> b) & 1u)
      px[bit / 8] = static_cast<std::uint8_t>(px[bit / 8] | (1u << (bit % 8)));
    else
      px[bit / 8] = static_cast<std::uint8_t>(px[bit / 8] & ~(1u << (bit % 8)));
  }
}

inline void put_le(std::uint8_t* p, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

/// Synthetic lidar packets of a metadata's layout.
struct PacketBuilder {
  OusterMetadata md;
  OusterPacketFormat fmt;
  std::uint64_t t0_ns = 1'000'000'000'000ull;  ///< sensor time of measurement 0 of frame 0
  std::uint32_t init_id = 0;
  std::uint64_t prod_sn = 0;

  explicit PacketBuilder(OusterMetadata m)
      : md(std::move(m)), fmt(md), init_id(md.init_id), prod_sn(md.prod_sn) {}

  /// Column time: frames at md.fps, columns evenly spaced.
  [[nodiscard]] std::uint64_t column_ns(std::uint32_t frame, int m) const {
    const double frame_ns = 1e9 / md.fps;
    return t0_ns + static_cast<std::uint64_t>(frame * frame_ns + m * frame_ns / md.columns_per_frame);
  }

  /// One packet of frame `frame` starting at measurement id `first_m`; `fill(m, row, pixel)`
  /// writes each pixel (all zero otherwise); `valid` is the columns' valid bit.
  [[nodiscard]] std::vector<std::uint8_t> packet(std::uint32_t frame, int first_m,
                                                 const std::function<void(int, int, std::uint8_t*)>& fill,
                                                 bool valid = true) const {
    std::vector<std::uint8_t> p(fmt.packet_size, 0);
    if (!fmt.legacy) {
      if (fmt.fusa_header) {
        p[0] = 1;
        put_le(&p[1], init_id, 3);
        put_le(&p[4], frame, 4);
        put_le(&p[11], prod_sn, 5);
      } else {
        put_le(&p[0], 1, 2);
        put_le(&p[2], frame & 0xFFFF, 2);
        put_le(&p[4], init_id, 3);
        put_le(&p[7], prod_sn, 5);
      }
    }
    for (int c = 0; c < fmt.columns_per_packet; ++c) {
      std::uint8_t* col = p.data() + fmt.packet_header_size + static_cast<std::size_t>(c) * fmt.column_size;
      const int m = first_m + c;
      put_le(col, column_ns(frame, m), 8);
      put_le(col + 8, static_cast<std::uint64_t>(m), 2);
      if (fmt.legacy) {
        put_le(col + 10, frame & 0xFFFF, 2);
        put_le(col + 12, static_cast<std::uint64_t>(m) * 88, 4);
        put_le(col + fmt.column_size - 4, valid ? 0xFFFFFFFFu : 0u, 4);
      } else {
        put_le(col + 10, valid ? 1 : 0, 2);
      }
      if (fill)
        for (int row = 0; row < fmt.pixels_per_column; ++row)
          fill(m, row, col + fmt.column_header_size + static_cast<std::size_t>(row) * fmt.pixel_size);
    }
    return p;
  }

  /// The packets of one whole frame (the column window only).
  [[nodiscard]] std::vector<std::vector<std::uint8_t>> frame(
      std::uint32_t frame_id, const std::function<void(int, int, std::uint8_t*)>& fill) const {
    std::vector<std::vector<std::uint8_t>> out;
    for (int m = 0; m < md.columns_per_frame; m += fmt.columns_per_packet)
      if (md.in_window(m)) out.push_back(packet(frame_id, m, fill));
    return out;
  }
};

/// Packets over byte buffers, stamped from a sensor-time origin, named "<name>: packet <i>".
inline std::vector<Packet> packets_of(const std::vector<std::vector<std::uint8_t>>& bufs,
                                      const std::string& name, double stamp0 = 0.0, double dt = 0.0,
                                      std::uint16_t port = 7502) {
  std::vector<Packet> out;
  for (std::size_t i = 0; i < bufs.size(); ++i) {
    Packet p;
    p.data = bufs[i].data();
    p.size = bufs[i].size();
    p.stamp = stamp0 > 0.0 ? stamp0 + dt * static_cast<double>(i) : 0.0;
    p.port = port;
    p.where = name + ": packet " + std::to_string(i);
    out.push_back(p);
  }
  return out;
}

}  // namespace ouster_test
