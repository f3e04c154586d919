// Hesai point-cloud data packets: the layouts of the supported protocol families, read in place.
//
//   Pandar40P    no header; 10 blocks of (FF EE, azimuth, 40 x 3 B); 22 B tail. 1262 B.
//   Pandar64     8 B header (EE FF, lasers, blocks, -, dis_unit, -, -); 6 blocks of (azimuth,
//                64 x 3 B); 22 B tail; optional 4 B UDP sequence. 1194 / 1198 B.
//   protocol 3.1 PandarQT64: 12 B header; 4 blocks of (azimuth, 64 x 4 B); 24 B tail; 4 B UDP
//                sequence when header flag bit 0. 1068 / 1072 B.
//   protocol 3.2 PandarQT128 (C2X): 12 B header; 2 blocks of (azimuth, 128 x 4 B); 4 B body CRC;
//                17 B functional safety (flag bit 2); 34 B tail with UDP sequence and tail CRC;
//                32 B signature (flag bit 3). 1127 B with both.
//   protocol 6.1 PandarXT16 / XT32 (8 blocks) / XT32M (6 blocks): 12 B header; blocks of
//                (azimuth, lasers x 4 B); 24 B tail; 4 B UDP sequence. 568 / 1080 / 820 B.
//
// The 12-byte header: EE FF, protocol major, minor, 2 reserved, lasers, blocks, first-block return,
// dis_unit (mm), returns, flags. All multi-byte fields are little-endian. Units: distance uint16 in
// dis_unit (Pandar40P: 4 mm), reflectivity uint8, then (4-byte units) one reserved/confidence byte.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "dloam/drivers/hesai_model.hpp"
#include "dloam/drivers/scanner.hpp"

namespace dloam::drivers::hesai {

/// A data packet's fields. Points into the packet's bytes: valid while they are.
struct PacketView {
  Model model = Model::kPandar40P;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  int blocks = 0;
  int channels = 0;
  std::uint8_t return_mode = 0;
  ReturnLayout layout;        ///< of return_mode
  double dis_unit_m = 0.004;  ///< distance unit (m)
  int dis_unit_mm = 4;        ///< the same, as the packet states it
  int motor_rpm = 0;          ///< motor speed field
  double sensor_time = 0.0;   ///< the packet's own timestamp (s since 1970, the sensor's clock)
  bool has_sequence = false;  ///< carries a UDP sequence number
  std::uint32_t sequence = 0;
  std::uint8_t mode_flag = 0;  ///< QT128: bit 0 set = firing sequence 1 in dual-return packets
  bool crc_checked = false;    ///< the packet carries CRCs (QT128) and they were checked
  bool crc_ok = true;          ///< all checked CRCs match

  std::size_t block_offset = 0;  ///< byte offset of block 0's azimuth field
  std::size_t block_stride = 0;  ///< bytes per block
  std::size_t unit_size = 3;     ///< bytes per channel unit

  /// Block azimuth in 0.01 deg.
  [[nodiscard]] std::uint16_t azimuth(int block) const {
    const std::uint8_t* p = data + block_offset + block_stride * static_cast<std::size_t>(block);
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
  }
  /// Unit of `channel` in `block`: distance (low, high), reflectivity, ...
  [[nodiscard]] const std::uint8_t* unit(int block, int channel) const {
    return data + block_offset + block_stride * static_cast<std::size_t>(block) + 2 +
           unit_size * static_cast<std::size_t>(channel);
  }
};

/// True for a Hesai GPS packet (512 bytes starting FF EE with a date), which the sensors send on
/// a port of their own; decoders ignore it.
bool is_gps_packet(const Packet& packet);
/// True when the packet has the magic and plausible size of a Hesai data packet (EE FF header,
/// or the 1262-byte Pandar40P packet of FF EE blocks). Cheap; no full validation.
bool looks_like_data_packet(const Packet& packet);
/// The model that sent a data packet, from its header (protocol version, laser and block counts)
/// or, for the header-less Pandar40P, its size. Throws InputError naming packet.where for an
/// unknown protocol version, an unsupported model or a size that does not fit the header.
Model identify_model(const Packet& packet);
/// Reads and validates a data packet of `model`: size for its header and flags, block markers,
/// laser and block counts, return mode, azimuths below 360 deg, CRCs (QT128; a mismatch sets
/// crc_ok = false). Throws InputError naming packet.where when the packet is not one of `model`'s.
PacketView parse_packet(const Packet& packet, Model model);

/// CRC-32/MPEG-2 (polynomial 0x04C11DB7, MSB first, init 0xFFFFFFFF, no final xor): the CRC of
/// the QT128's body and tail.
std::uint32_t crc32_mpeg2(const std::uint8_t* data, std::size_t size);

}  // namespace dloam::drivers::hesai
