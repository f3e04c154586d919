// libFuzzer harness: rosbag2 folders through their metadata.yaml: the input is written as the
// metadata of a folder that also holds a small valid storage file (bag_0.db3, made once at start),
// then the folder is opened as a bag and its messages read.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "dloam/io/bag.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "fuzz_util.hpp"

namespace {
namespace fs = std::filesystem;
const std::string& folder() {
  static const std::string dir = "/tmp/dloam-fuzz-meta-" + std::to_string(::getpid());
  return dir;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fs::remove_all(folder());
  dloam::io::Rosbag2Writer w(folder());  // folder()/metadata.yaml and folder()/<name>_0.db3
  w.add_topic("/points", "sensor_msgs/msg/PointCloud2");
  const std::uint8_t junk[8] = {0, 1, 0, 0, 1, 2, 3, 4};
  for (int k = 0; k < 3; ++k) w.write("/points", 1000 + k, junk, sizeof(junk));
  w.close();
  for (const auto& e : fs::directory_iterator(folder()))
    if (e.path().extension() == ".db3") fs::rename(e.path(), fs::path(folder()) / "bag_0.db3");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(folder() + "/metadata.yaml", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  dloam::fuzz::expect_input_error_or_success([&] {
    const dloam::io::Bag bag(folder());
    (void)bag.describe();
    for (const auto& topic : bag.topics())
      for (std::size_t k = 0; k < bag.message_count(topic.name) && k < 4; ++k) (void)bag.read(topic.name, k);
  });
  return 0;
}
