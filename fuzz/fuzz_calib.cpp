// libFuzzer harness: KITTI calib.txt (KEY: values, Tr / Tr_velo_to_cam, P0..P3).
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] { (void)dloam::io::parse_calib(input, "calib.txt"); });
  return 0;
}
