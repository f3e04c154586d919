// libFuzzer harness: KITTI times.txt (one increasing time per line).
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] { (void)dloam::io::parse_times(input, "times.txt"); });
  return 0;
}
