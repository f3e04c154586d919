// libFuzzer harness: TUM trajectories (t tx ty tz qx qy qz qw).
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success(
      [&] { (void)dloam::io::parse_tum_poses(input, "poses_tum.txt"); });
  return 0;
}
