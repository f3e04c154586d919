// libFuzzer harness: PLY point clouds (ascii and binary little-endian vertex elements).
#include <cstddef>
#include <cstdint>

#include "dloam/io/ply.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] { (void)dloam::io::parse_ply(input, "fuzz.ply"); });
  return 0;
}
