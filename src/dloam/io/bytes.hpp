// Unaligned big- / little-endian loads and stores of fixed-size integers and floats, for the
// binary container formats (pcap frames, CDR, MCAP). Internal to dloam_io.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace dloam::io::detail {

inline std::uint16_t load_be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((static_cast<unsigned>(p[0]) << 8) | p[1]);
}
inline std::uint32_t load_be32(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
         (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
}

/// Reads a T stored in little-endian (`big` = false) or big-endian byte order.
template <class T>
T load_scalar_as(const std::uint8_t* p, bool big) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::uint8_t buf[sizeof(T)];
  if (big) {
    for (std::size_t i = 0; i < sizeof(T); ++i) buf[i] = p[sizeof(T) - 1 - i];
  } else {
    std::memcpy(buf, p, sizeof(T));
  }
  T v;
  std::memcpy(&v, buf, sizeof(T));
  return v;
}

template <class T>
T load_le(const std::uint8_t* p) {
  return load_scalar_as<T>(p, false);
}

template <class T>
void store_le(std::uint8_t* p, T v) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::memcpy(p, &v, sizeof(T));
}

}  // namespace dloam::io::detail
