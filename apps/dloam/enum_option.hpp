// Command-line values of the configuration's enumerations, spelt as in the YAML
// (core/enum_names.hpp).
#pragma once

#include <string>
#include <vector>

#include "dloam/core/enum_names.hpp"

namespace dloam::app {

/// Every name of E's table, for CLI::IsMember.
template <class E>
std::vector<std::string> enum_names_of() {
  std::vector<std::string> out;
  for (const auto& entry : enum_names(E{})) out.emplace_back(entry.name);
  return out;
}

}  // namespace dloam::app
