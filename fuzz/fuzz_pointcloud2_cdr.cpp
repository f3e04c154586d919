// libFuzzer harness: sensor_msgs/msg/PointCloud2 in CDR (ROS 2 bags): the encapsulation header,
// strings and sequences, the field table, the point layout and the conversion to a cloud.
#include <cstddef>
#include <cstdint>

#include "dloam/io/pointcloud2_cdr.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dloam::fuzz::expect_input_error_or_success([&] {
    double stamp = 0.0;
    const auto converted = dloam::io::read_pointcloud2(data, size, "fuzz.cdr", &stamp);
    if (converted.cloud.empty()) __builtin_trap();  // an empty cloud is an error, not a result
  });
  return 0;
}
