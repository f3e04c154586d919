// libFuzzer harness: KITTI poses.txt (3x4 row-major matrices) and the camera -> LiDAR frame change.
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] {
    const auto poses = dloam::io::parse_kitti_poses(input, "poses.txt");
    (void)dloam::io::camera_to_lidar(poses, poses.empty() ? dloam::Pose::Identity() : poses.front());
  });
  return 0;
}
