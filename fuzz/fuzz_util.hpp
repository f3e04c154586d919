// Shared by the libFuzzer harnesses: the input as bytes, and the contract every reader keeps: bad
// input throws dloam::InputError (any other exception escapes and is reported as a crash).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "dloam/core/types.hpp"

namespace dloam::fuzz {

inline std::string bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `read`; an InputError is the expected outcome for bad input.
template <class F>
void expect_input_error_or_success(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace dloam::fuzz
