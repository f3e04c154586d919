// libFuzzer harness: Ouster sensor metadata JSON (every firmware layout the reader knows).
#include <cstddef>
#include <cstdint>

#include "dloam/drivers/ouster_metadata.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success(
      [&] { (void)dloam::drivers::parse_ouster_metadata(input, "fuzz.json"); });
  return 0;
}
