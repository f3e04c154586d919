// libFuzzer harness: Velodyne calibration files, ROS YAML and VeloView XML (the reader takes a
// path, so the input goes through a temporary file; a leading '<' makes it the XML kind).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "dloam/drivers/velodyne_calibration.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool xml = size > 0 && data[0] == '<';
  const std::string path = "/tmp/dloam-fuzz-" + std::to_string(::getpid()) + (xml ? ".xml" : ".yaml");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  dloam::fuzz::expect_input_error_or_success([&] {
    auto calibration = dloam::drivers::read_velodyne_calibration(path);
    dloam::drivers::assign_velodyne_rings(calibration);
  });
  std::remove(path.c_str());
  return 0;
}
