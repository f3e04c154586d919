// libFuzzer harness: rosbag2 SQLite storage files (.db3, from memory): the schema, topics,
// message rows; then the messages of every topic.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dloam/io/bag.hpp"
#include "fuzz_bag.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dloam::fuzz::expect_input_error_or_success([&] {
    auto file =
        dloam::io::bag_detail::open_sqlite_memory(std::vector<std::uint8_t>(data, data + size), "fuzz.db3");
    dloam::fuzz::read_bag_file(*file);
  });
  return 0;
}
