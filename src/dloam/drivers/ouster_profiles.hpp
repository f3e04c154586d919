// Byte layout of Ouster lidar packets per UDP profile: packet header and footer, column header
// (timestamp, measurement_id, status, and for LEGACY frame_id and encoder count), and the channel
// fields of a pixel with their bit positions (the field tables published with ouster-sdk).
// All values are little-endian.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "dloam/drivers/ouster_metadata.hpp"

namespace dloam::drivers {

/// Channel fields of a pixel (ouster-sdk's ChanField names).
enum class OusterField : std::uint8_t {
  kRange,
  kRange2,
  kFlags,
  kFlags2,
  kReflectivity,
  kReflectivity2,
  kSignal,
  kSignal2,
  kNearIr,
  kRaw32Word1,
  kRaw32Word2,
  kRaw32Word3,
  kRaw32Word4,
};

/// "RANGE", "REFLECTIVITY2", "RAW32_WORD1", ...
const char* to_string(OusterField field);

/// Where a field sits in a pixel: `bits` bits from bit `bit_start`, shifted up by `upshift`
/// (RNG15 ranges are in 8 mm units: upshift 3 gives mm).
struct OusterFieldLayout {
  OusterField field;
  int bit_start = 0, bits = 0, upshift = 0;

  /// The value (after mask and upshift) from the pixel's first byte.
  [[nodiscard]] std::uint32_t decode(const std::uint8_t* pixel) const {
    std::uint32_t word = 0;
    if (nbytes_ == 4) {
      std::memcpy(&word, pixel + byte_, 4);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
      word = __builtin_bswap32(word);
#endif
    } else {
      for (int i = 0; i < nbytes_; ++i) word |= static_cast<std::uint32_t>(pixel[byte_ + i]) << (8 * i);
    }
    return ((word >> shift_) & mask_) << upshift;
  }
  /// Bytes of the smallest unsigned type that holds bits + upshift (1, 2 or 4).
  [[nodiscard]] int value_bytes() const;

  /// `pixel_size`: bytes of a pixel (the decoder reads whole 32-bit words where they fit).
  OusterFieldLayout(OusterField f, int start, int n, int up, std::size_t pixel_size);

 private:
  int byte_ = 0, nbytes_ = 0, shift_ = 0;
  std::uint32_t mask_ = 0;
};

/// The layout of one stream's lidar packets, from its metadata.
class OusterPacketFormat {
 public:
  explicit OusterPacketFormat(const OusterMetadata& metadata);

  OusterProfile profile;
  bool legacy, fusa_header;
  int pixels_per_column, columns_per_packet;
  std::size_t packet_header_size, column_header_size, pixel_size, column_footer_size, packet_footer_size;
  std::size_t column_size, packet_size;

  /// The profile's fields in ouster-sdk's table order.
  [[nodiscard]] const std::vector<OusterFieldLayout>& fields() const { return fields_; }
  /// A field of the profile, or nullptr when the profile has none of that name.
  [[nodiscard]] const OusterFieldLayout* field(OusterField f) const;
  [[nodiscard]] bool dual() const { return field(OusterField::kRange2) != nullptr; }

  // Packet header (non-LEGACY; LEGACY packets carry the frame id in each column).
  [[nodiscard]] std::uint16_t packet_type(const std::uint8_t* packet) const;
  [[nodiscard]] std::uint32_t frame_id(const std::uint8_t* packet) const;
  [[nodiscard]] std::uint32_t init_id(const std::uint8_t* packet) const;
  [[nodiscard]] std::uint64_t prod_sn(const std::uint8_t* packet) const;
  /// Largest frame id + 1 (2^16, or 2^32 for the FuSa header).
  [[nodiscard]] std::uint64_t frame_id_modulus() const { return fusa_header ? (1ull << 32) : (1ull << 16); }

  // Columns.
  [[nodiscard]] const std::uint8_t* column(const std::uint8_t* packet, int c) const {
    return packet + packet_header_size + static_cast<std::size_t>(c) * column_size;
  }
  [[nodiscard]] std::uint64_t col_timestamp(const std::uint8_t* col) const;
  [[nodiscard]] std::uint16_t col_measurement_id(const std::uint8_t* col) const;
  /// LEGACY: the 32-bit column status after the pixels (0xFFFFFFFF valid); otherwise the 16-bit
  /// status at column byte 10. Bit 0 set: the column is valid.
  [[nodiscard]] std::uint32_t col_status(const std::uint8_t* col) const;
  [[nodiscard]] std::uint32_t col_encoder(const std::uint8_t* col) const;   ///< LEGACY only, else 0
  [[nodiscard]] std::uint16_t col_frame_id(const std::uint8_t* col) const;  ///< LEGACY only, else 0
  [[nodiscard]] const std::uint8_t* pixel(const std::uint8_t* col, int px) const {
    return col + column_header_size + static_cast<std::size_t>(px) * pixel_size;
  }

  /// Packets of this profile carry a CRC-64 footer when the firmware writes one (not LEGACY, not
  /// the FuSa header).
  [[nodiscard]] bool may_have_crc() const { return !legacy && !fusa_header; }
  /// The CRC stored in the last 8 bytes, and the one computed over the rest (CRC-64/XZ:
  /// ECMA-182 polynomial, reflected, init and xorout all ones).
  [[nodiscard]] std::uint64_t stored_crc(const std::uint8_t* packet, std::size_t size) const;
  [[nodiscard]] static std::uint64_t compute_crc(const std::uint8_t* packet, std::size_t size);

 private:
  std::vector<OusterFieldLayout> fields_;
  std::array<int, 16> index_{};  ///< OusterField -> position in fields_, -1 absent
};

/// Little-endian unsigned load of N bytes.
template <typename T>
inline T load_le(const std::uint8_t* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(p[i]) << (8 * i));
  return v;
}

}  // namespace dloam::drivers
