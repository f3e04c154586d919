// Record layouts of the binary point formats (PCD, PLY) and scalar loading.
#include "dloam/io/fields.hpp"

#include <cstdint>
#include <cstring>

namespace dloam::io::detail {

namespace {
template <class T>
double load(const char* bytes) {
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return static_cast<double>(v);
}
}  // namespace

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::kI8:
    case ScalarType::kU8:
      return 1;
    case ScalarType::kI16:
    case ScalarType::kU16:
      return 2;
    case ScalarType::kI32:
    case ScalarType::kU32:
    case ScalarType::kF32:
      return 4;
    case ScalarType::kI64:
    case ScalarType::kU64:
    case ScalarType::kF64:
      return 8;
  }
  return 0;
}

double load_scalar(ScalarType type, const char* bytes) {
  switch (type) {
    case ScalarType::kI8:
      return load<std::int8_t>(bytes);
    case ScalarType::kU8:
      return load<std::uint8_t>(bytes);
    case ScalarType::kI16:
      return load<std::int16_t>(bytes);
    case ScalarType::kU16:
      return load<std::uint16_t>(bytes);
    case ScalarType::kI32:
      return load<std::int32_t>(bytes);
    case ScalarType::kU32:
      return load<std::uint32_t>(bytes);
    case ScalarType::kI64:
      return load<std::int64_t>(bytes);
    case ScalarType::kU64:
      return load<std::uint64_t>(bytes);
    case ScalarType::kF32:
      return load<float>(bytes);
    case ScalarType::kF64:
      return load<double>(bytes);
  }
  return 0.0;
}

void Layout::add(const std::string& name, ScalarType type, std::size_t count) {
  fields.push_back({name, type, count, stride, columns});
  stride += scalar_size(type) * count;
  columns += count;
}

std::optional<Field> Layout::find(std::initializer_list<const char*> names) const {
  for (const auto& f : fields)
    for (const char* n : names)
      if (f.name == n) return f;
  return std::nullopt;
}

}  // namespace dloam::io::detail
