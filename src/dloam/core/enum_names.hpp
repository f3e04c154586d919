// Names of the enumerations that configure the modules, one table per enumeration beside its
// declaration: `enum_names(E{})` returns an array of {value, name}. The YAML schema, the command
// line and the Python module read and print the values by these names, so an option is spelt the
// same everywhere.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace dloam {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of `value` in its table (empty when the table lacks it).
template <class E>
[[nodiscard]] std::string_view name_of(E value) {
  for (const auto& entry : enum_names(E{}))
    if (entry.value == value) return entry.name;
  return {};
}

/// The value named `name` (exact spelling), or nothing.
template <class E>
[[nodiscard]] std::optional<E> enum_from_name(std::string_view name) {
  for (const auto& entry : enum_names(E{}))
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

/// Every name of the table joined by `separator`, in table order (for messages and help texts).
template <class E>
[[nodiscard]] std::string enum_choices(std::string_view separator = " | ") {
  std::string out;
  for (const auto& entry : enum_names(E{})) {
    if (!out.empty()) out += separator;
    out += entry.name;
  }
  return out;
}

}  // namespace dloam
