// libFuzzer harness: the ROS 1 bag reader (the rosbag library reads a file, so the input goes
// through a temporary one): opening, topic choice, header stamps, PointCloud2 conversion.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "dloam/ros/bag_sequence.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/dloam-fuzz-" + std::to_string(::getpid()) + ".bag";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  dloam::fuzz::expect_input_error_or_success([&] {
    const dloam::io::Sequence seq = dloam::ros1::open_bag_sequence(path, "");
    for (std::size_t i = 0; i < seq.size() && i < 8; ++i) (void)seq.read_scan(i);
    (void)seq.source->describe();
  });
  std::remove(path.c_str());
  return 0;
}
