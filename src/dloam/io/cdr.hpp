// OMG CDR (XCDR1 as ROS 2 writes it, and plain XCDR2) decoding and encoding of ROS 2 messages.
// A message starts with a 4-byte encapsulation header (00 00 big-endian, 00 01 little-endian;
// 00 06 / 00 07 XCDR2); fields are aligned to their size relative to the byte after it (XCDR2:
// at most 4). Every read is bounds-checked: a message shorter than its fields is an
// InputError "<where>: message shorter than its fields (<field> ...)".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dloam::io {

class CdrReader {
 public:
  /// `where` names the message in errors ("drive.db3: topic /points, message 12").
  CdrReader(const std::uint8_t* data, std::size_t size, std::string where);

  [[nodiscard]] bool big_endian() const { return big_; }
  /// Bytes of the message after the encapsulation header.
  [[nodiscard]] std::size_t size() const { return size_; }
  /// Read position relative to the byte after the header.
  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return size_ - pos_; }
  [[nodiscard]] const std::string& where() const { return where_; }

  std::uint8_t u8(const char* field);
  bool boolean(const char* field) { return u8(field) != 0; }
  std::uint16_t u16(const char* field);
  std::int32_t i32(const char* field);
  std::uint32_t u32(const char* field);
  std::uint64_t u64(const char* field);
  double f64(const char* field);
  /// A CDR string: uint32 length including the terminating NUL, the bytes, the NUL.
  std::string string(const char* field);
  /// `n` raw bytes (a uint8[n] array: no alignment); returns a pointer into the message.
  const std::uint8_t* bytes(std::size_t n, const char* field);
  /// A uint8[] sequence: uint32 count, then the bytes; `n` is set to the count.
  const std::uint8_t* byte_sequence(std::size_t& n, const char* field);
  /// A sequence count that must fit the remaining bytes at `min_element_size` bytes each.
  std::uint32_t sequence_count(std::size_t min_element_size, const char* field);
  void align(std::size_t n);
  /// Throws "message shorter than its fields" unless `n` more bytes are there.
  void need(std::size_t n, const char* field) const;

  /// Throws InputError "<where>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  template <class T>
  T scalar(const char* field);
  const std::uint8_t* data_ = nullptr;  ///< after the header
  std::size_t size_ = 0, pos_ = 0;
  bool big_ = false;
  std::size_t max_align_ = 8;
  std::string where_;
};

/// Little-endian XCDR1 encoding (what ROS 2 writes), the mirror of CdrReader.
class CdrWriter {
 public:
  CdrWriter();
  void u8(std::uint8_t v);
  void boolean(bool v) { u8(v ? 1 : 0); }
  void u16(std::uint16_t v);
  void i32(std::int32_t v);
  void u32(std::uint32_t v);
  void f64(double v);
  void string(const std::string& s);
  void bytes(const std::uint8_t* data, std::size_t n);
  void byte_sequence(const std::uint8_t* data, std::size_t n);
  void align(std::size_t n);
  [[nodiscard]] const std::vector<std::uint8_t>& data() const { return buf_; }
  std::vector<std::uint8_t> take() { return std::move(buf_); }

 private:
  template <class T>
  void scalar(T v);
  std::vector<std::uint8_t> buf_;
};

}  // namespace dloam::io
