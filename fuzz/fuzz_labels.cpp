// libFuzzer harness: SemanticKITTI .label files, with the right and a wrong point count.
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success(
      [&] { (void)dloam::io::parse_labels(input, "fuzz.label", size / 4); });
  dloam::fuzz::expect_input_error_or_success([&] { (void)dloam::io::parse_labels(input, "fuzz.label", 7); });
  return 0;
}
