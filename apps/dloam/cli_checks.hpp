// CLI11 validators of the numbers the commands take, with plain messages ("must be an integer >= 1").
#pragma once

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

namespace dloam::app {

/// An integer >= `lo`.
inline CLI::Validator integer_at_least(long lo) {
  return CLI::Validator(
      [lo](const std::string& text) {
        errno = 0;
        char* end = nullptr;
        const long v = std::strtol(text.c_str(), &end, 10);
        const bool ok = !text.empty() && end && *end == '\0' && errno == 0 && v >= lo;
        return ok ? std::string() : "must be an integer >= " + std::to_string(lo) + ", got '" + text + "'";
      },
      "INT>=" + std::to_string(lo));
}

/// A finite number > 0.
inline CLI::Validator positive_number() {
  return CLI::Validator(
      [](const std::string& text) {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool ok = !text.empty() && end && *end == '\0' && std::isfinite(v) && v > 0.0;
        return ok ? std::string() : "must be a number > 0, got '" + text + "'";
      },
      "NUMBER>0");
}

}  // namespace dloam::app
