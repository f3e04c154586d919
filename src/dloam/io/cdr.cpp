// CDR decoding / encoding (see cdr.hpp).
#include "dloam/io/cdr.hpp"

#include <algorithm>
#include <cstring>

#include "dloam/core/types.hpp"
#include "dloam/io/bytes.hpp"

namespace dloam::io {

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::string where)
    : where_(std::move(where)) {
  if (size < 4)
    fail("message shorter than its fields (" + std::to_string(size) +
         " bytes, no 4-byte CDR encapsulation header)");
  if (data[0] != 0)
    fail("not a CDR message (encapsulation header " + std::to_string(data[0]) + " " +
         std::to_string(data[1]) + ")");
  switch (data[1]) {
    case 0x00:  // CDR_BE
    case 0x01:  // CDR_LE
      big_ = data[1] == 0x00;
      max_align_ = 8;
      break;
    case 0x06:  // CDR2_BE
    case 0x07:  // CDR2_LE
      big_ = data[1] == 0x06;
      max_align_ = 4;
      break;
    default:
      fail("unsupported CDR encapsulation " + std::to_string(data[1]) +
           " (plain CDR / XCDR2 only, not parameter lists)");
  }
  data_ = data + 4;
  size_ = size - 4;
}

void CdrReader::fail(const std::string& what) const { throw InputError(where_ + ": " + what); }

void CdrReader::need(std::size_t n, const char* field) const {
  if (n > size_ - pos_)
    fail(std::string("message shorter than its fields (") + field + ": needs " + std::to_string(n) +
         " bytes at offset " + std::to_string(pos_ + 4) + ", the message has " + std::to_string(size_ + 4) +
         ")");
}

void CdrReader::align(std::size_t n) {
  if (n > max_align_) n = max_align_;
  const std::size_t pad = (n - pos_ % n) % n;
  pos_ = std::min(size_, pos_ + pad);  // padding past the end: the next read fails
}

template <class T>
T CdrReader::scalar(const char* field) {
  const std::size_t a = std::min(sizeof(T), max_align_);
  const std::size_t pad = (a - pos_ % a) % a;
  need(pad + sizeof(T), field);
  pos_ += pad;
  const T v = detail::load_scalar_as<T>(data_ + pos_, big_);
  pos_ += sizeof(T);
  return v;
}

std::uint8_t CdrReader::u8(const char* field) { return scalar<std::uint8_t>(field); }
std::uint16_t CdrReader::u16(const char* field) { return scalar<std::uint16_t>(field); }
std::int32_t CdrReader::i32(const char* field) { return scalar<std::int32_t>(field); }
std::uint32_t CdrReader::u32(const char* field) { return scalar<std::uint32_t>(field); }
std::uint64_t CdrReader::u64(const char* field) { return scalar<std::uint64_t>(field); }
double CdrReader::f64(const char* field) { return scalar<double>(field); }

std::string CdrReader::string(const char* field) {
  const std::uint32_t n = u32(field);
  if (n == 0) return {};  // some writers omit the NUL of an empty string
  need(n, field);
  const char* s = reinterpret_cast<const char*>(data_ + pos_);
  pos_ += n;
  return std::string(s, s[n - 1] == '\0' ? n - 1 : n);
}

const std::uint8_t* CdrReader::bytes(std::size_t n, const char* field) {
  need(n, field);
  const std::uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

const std::uint8_t* CdrReader::byte_sequence(std::size_t& n, const char* field) {
  n = u32(field);
  return bytes(n, field);
}

std::uint32_t CdrReader::sequence_count(std::size_t min_element_size, const char* field) {
  const std::uint32_t n = u32(field);
  if (min_element_size > 0 && n > remaining() / min_element_size)
    fail(std::string("message shorter than its fields (") + field + ": " + std::to_string(n) +
         " elements of at least " + std::to_string(min_element_size) + " bytes announced, " +
         std::to_string(remaining()) + " bytes left)");
  return n;
}

CdrWriter::CdrWriter() : buf_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::align(std::size_t n) {
  const std::size_t pos = buf_.size() - 4;
  buf_.resize(buf_.size() + (n - pos % n) % n, 0);
}

template <class T>
void CdrWriter::scalar(T v) {
  align(sizeof(T));
  const std::size_t at = buf_.size();
  buf_.resize(at + sizeof(T));
  std::memcpy(buf_.data() + at, &v, sizeof(T));
}

void CdrWriter::u8(std::uint8_t v) { buf_.push_back(v); }
void CdrWriter::u16(std::uint16_t v) { scalar(v); }
void CdrWriter::i32(std::int32_t v) { scalar(v); }
void CdrWriter::u32(std::uint32_t v) { scalar(v); }
void CdrWriter::f64(double v) { scalar(v); }

void CdrWriter::string(const std::string& s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  buf_.insert(buf_.end(), s.begin(), s.end());
  buf_.push_back(0);
}

void CdrWriter::bytes(const std::uint8_t* data, std::size_t n) { buf_.insert(buf_.end(), data, data + n); }

void CdrWriter::byte_sequence(const std::uint8_t* data, std::size_t n) {
  u32(static_cast<std::uint32_t>(n));
  bytes(data, n);
}

}  // namespace dloam::io
