// Record layouts of the binary point formats (PCD, PLY): named scalar fields at byte offsets,
// and loading one little-endian scalar as double. Internal to dloam_io.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dloam::io::detail {

enum class ScalarType { kI8, kU8, kI16, kU16, kI32, kU32, kI64, kU64, kF32, kF64 };

std::size_t scalar_size(ScalarType type);
/// Reads one little-endian scalar (the host's byte order: x86 / ARM) as double.
double load_scalar(ScalarType type, const char* bytes);

struct Field {
  std::string name;
  ScalarType type = ScalarType::kF32;
  std::size_t count = 1;   ///< elements (PCD COUNT)
  std::size_t offset = 0;  ///< byte offset in the record; also the element index in ascii records
  std::size_t column = 0;  ///< index of the first value in an ascii record
};

/// A record layout: fields in order, offsets filled in by add().
struct Layout {
  std::vector<Field> fields;
  std::size_t stride = 0;   ///< bytes per binary record
  std::size_t columns = 0;  ///< values per ascii record
  void add(const std::string& name, ScalarType type, std::size_t count = 1);
  /// The first field with one of these names, if any.
  [[nodiscard]] std::optional<Field> find(std::initializer_list<const char*> names) const;
};

}  // namespace dloam::io::detail
