// libFuzzer harness: KITTI velodyne .bin scans (float32 x y z intensity records).
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] { (void)dloam::io::parse_kitti_bin(input, "fuzz.bin"); });
  return 0;
}
