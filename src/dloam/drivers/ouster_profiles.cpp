#include "dloam/drivers/ouster_profiles.hpp"

#include <lzma.h>

#include <algorithm>
#include <stdexcept>

namespace dloam::drivers {

namespace {

struct FieldSpec {
  OusterField field;
  int bit_start, bits, upshift;
};

using F = OusterField;

// The field tables published with ouster-sdk, in its order. The WINDOW byte that newer releases
// define in some profiles is not decoded.
const std::vector<FieldSpec> kLegacy = {
    {F::kRange, 0, 20, 0},       {F::kFlags, 28, 4, 0},       {F::kReflectivity, 32, 8, 0},
    {F::kSignal, 48, 16, 0},     {F::kNearIr, 64, 16, 0},     {F::kRaw32Word1, 0, 32, 0},
    {F::kRaw32Word2, 32, 32, 0}, {F::kRaw32Word3, 64, 32, 0},
};
const std::vector<FieldSpec> kSingle = {
    {F::kRange, 0, 19, 0},       {F::kFlags, 19, 5, 0},       {F::kReflectivity, 32, 8, 0},
    {F::kSignal, 48, 16, 0},     {F::kNearIr, 64, 16, 0},     {F::kRaw32Word1, 0, 32, 0},
    {F::kRaw32Word2, 32, 32, 0}, {F::kRaw32Word3, 64, 32, 0},
};
const std::vector<FieldSpec> kDual = {
    {F::kRange, 0, 19, 0},       {F::kFlags, 19, 5, 0},       {F::kReflectivity, 24, 8, 0},
    {F::kRange2, 32, 19, 0},     {F::kFlags2, 51, 5, 0},      {F::kReflectivity2, 56, 8, 0},
    {F::kSignal, 64, 16, 0},     {F::kSignal2, 80, 16, 0},    {F::kNearIr, 96, 16, 0},
    {F::kRaw32Word1, 0, 32, 0},  {F::kRaw32Word2, 32, 32, 0}, {F::kRaw32Word3, 64, 32, 0},
    {F::kRaw32Word4, 96, 32, 0},
};
const std::vector<FieldSpec> kLowDataRate = {
    {F::kRange, 0, 15, 3},  {F::kFlags, 15, 1, 0},      {F::kReflectivity, 16, 8, 0},
    {F::kNearIr, 24, 8, 4}, {F::kRaw32Word1, 0, 32, 0},
};
const std::vector<FieldSpec> kLowDataRateDual = {
    {F::kRange, 0, 15, 3},         {F::kFlags, 15, 1, 0},      {F::kReflectivity, 16, 8, 0},
    {F::kNearIr, 24, 8, 4},        {F::kRange2, 32, 15, 3},    {F::kFlags2, 47, 1, 0},
    {F::kReflectivity2, 48, 8, 0}, {F::kRaw32Word1, 0, 32, 0}, {F::kRaw32Word2, 32, 32, 0},
};

const std::vector<FieldSpec>& table_of(OusterProfile p) {
  switch (p) {
    case OusterProfile::kLegacy:
      return kLegacy;
    case OusterProfile::kSingle:
      return kSingle;
    case OusterProfile::kDual:
      return kDual;
    case OusterProfile::kLowDataRate:
      return kLowDataRate;
    case OusterProfile::kLowDataRateDual:
    case OusterProfile::kFusaLowDataRateDual:
      return kLowDataRateDual;
  }
  throw std::logic_error("ouster: unknown profile");
}

std::size_t pixel_size_of(OusterProfile p) {
  switch (p) {
    case OusterProfile::kLegacy:
    case OusterProfile::kSingle:
      return 12;
    case OusterProfile::kDual:
      return 16;
    case OusterProfile::kLowDataRate:
      return 4;
    case OusterProfile::kLowDataRateDual:
    case OusterProfile::kFusaLowDataRateDual:
      return 8;
  }
  throw std::logic_error("ouster: unknown profile");
}

}  // namespace

const char* to_string(OusterField f) {
  switch (f) {
    case F::kRange:
      return "RANGE";
    case F::kRange2:
      return "RANGE2";
    case F::kFlags:
      return "FLAGS";
    case F::kFlags2:
      return "FLAGS2";
    case F::kReflectivity:
      return "REFLECTIVITY";
    case F::kReflectivity2:
      return "REFLECTIVITY2";
    case F::kSignal:
      return "SIGNAL";
    case F::kSignal2:
      return "SIGNAL2";
    case F::kNearIr:
      return "NEAR_IR";
    case F::kRaw32Word1:
      return "RAW32_WORD1";
    case F::kRaw32Word2:
      return "RAW32_WORD2";
    case F::kRaw32Word3:
      return "RAW32_WORD3";
    case F::kRaw32Word4:
      return "RAW32_WORD4";
  }
  return "?";
}

OusterFieldLayout::OusterFieldLayout(OusterField f, int start, int n, int up, std::size_t pixel_size)
    : field(f), bit_start(start), bits(n), upshift(up) {
  byte_ = start / 8;
  shift_ = start % 8;
  nbytes_ = (shift_ + n + 7) / 8;
  if (nbytes_ > 4 || static_cast<std::size_t>(byte_ + nbytes_) > pixel_size)
    throw std::logic_error("ouster: field outside its pixel");
  // One 32-bit load inside the pixel: from the field's first byte, or from the pixel's last
  // four bytes for a field near its end.
  if (pixel_size >= 4) {
    const int excess = byte_ + 4 - static_cast<int>(pixel_size);
    if (excess > 0) {
      byte_ -= excess;
      shift_ += 8 * excess;
    }
    nbytes_ = 4;
  }
  mask_ = n >= 32 ? 0xFFFFFFFFu : ((1u << n) - 1u);
}

int OusterFieldLayout::value_bytes() const {
  const int b = bits + upshift;
  return b <= 8 ? 1 : (b <= 16 ? 2 : 4);
}

OusterPacketFormat::OusterPacketFormat(const OusterMetadata& md)
    : profile(md.profile),
      legacy(md.profile == OusterProfile::kLegacy),
      fusa_header(md.fusa_header && md.profile != OusterProfile::kLegacy),
      pixels_per_column(md.pixels_per_column),
      columns_per_packet(md.columns_per_packet) {
  packet_header_size = legacy ? 0 : 32;
  column_header_size = legacy ? 16 : 12;
  pixel_size = pixel_size_of(profile);
  column_footer_size = legacy ? 4 : 0;
  packet_footer_size = legacy ? 0 : 32;
  column_size =
      column_header_size + static_cast<std::size_t>(pixels_per_column) * pixel_size + column_footer_size;
  packet_size =
      packet_header_size + static_cast<std::size_t>(columns_per_packet) * column_size + packet_footer_size;
  index_.fill(-1);
  for (const auto& s : table_of(profile)) {
    index_[static_cast<std::size_t>(s.field)] = static_cast<int>(fields_.size());
    fields_.emplace_back(s.field, s.bit_start, s.bits, s.upshift, pixel_size);
  }
}

const OusterFieldLayout* OusterPacketFormat::field(OusterField f) const {
  const int i = index_[static_cast<std::size_t>(f)];
  return i < 0 ? nullptr : &fields_[static_cast<std::size_t>(i)];
}

std::uint16_t OusterPacketFormat::packet_type(const std::uint8_t* p) const {
  if (legacy) return 0;
  return fusa_header ? p[0] : load_le<std::uint16_t>(p);
}

std::uint32_t OusterPacketFormat::frame_id(const std::uint8_t* p) const {
  if (legacy) return load_le<std::uint16_t>(p + 10);  // the first column's frame id
  return fusa_header ? load_le<std::uint32_t>(p + 4) : load_le<std::uint16_t>(p + 2);
}

std::uint32_t OusterPacketFormat::init_id(const std::uint8_t* p) const {
  if (legacy) return 0;
  const std::uint8_t* q = p + (fusa_header ? 1 : 4);
  return static_cast<std::uint32_t>(q[0]) | static_cast<std::uint32_t>(q[1]) << 8 |
         static_cast<std::uint32_t>(q[2]) << 16;
}

std::uint64_t OusterPacketFormat::prod_sn(const std::uint8_t* p) const {
  if (legacy) return 0;
  const std::uint8_t* q = p + (fusa_header ? 11 : 7);
  std::uint64_t sn = 0;
  for (int i = 0; i < 5; ++i) sn |= static_cast<std::uint64_t>(q[i]) << (8 * i);
  return sn;
}

std::uint64_t OusterPacketFormat::col_timestamp(const std::uint8_t* col) const {
  return load_le<std::uint64_t>(col);
}

std::uint16_t OusterPacketFormat::col_measurement_id(const std::uint8_t* col) const {
  return load_le<std::uint16_t>(col + 8);
}

std::uint32_t OusterPacketFormat::col_status(const std::uint8_t* col) const {
  if (legacy) return load_le<std::uint32_t>(col + column_size - 4);
  return load_le<std::uint16_t>(col + 10);
}

std::uint32_t OusterPacketFormat::col_encoder(const std::uint8_t* col) const {
  return legacy ? load_le<std::uint32_t>(col + 12) : 0;
}

std::uint16_t OusterPacketFormat::col_frame_id(const std::uint8_t* col) const {
  return legacy ? load_le<std::uint16_t>(col + 10) : 0;
}

std::uint64_t OusterPacketFormat::stored_crc(const std::uint8_t* packet, std::size_t size) const {
  return size < 8 ? 0 : load_le<std::uint64_t>(packet + size - 8);
}

std::uint64_t OusterPacketFormat::compute_crc(const std::uint8_t* packet, std::size_t size) {
  return size < 8 ? 0 : lzma_crc64(packet, size - 8, 0);
}

}  // namespace dloam::drivers
