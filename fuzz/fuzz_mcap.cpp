// libFuzzer harness: MCAP files (from memory): magic, records, chunks (lz4 / zstd), summary and
// message indexes, the linear scan; then the messages of every topic.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dloam/io/bag.hpp"
#include "dloam/io/mcap.hpp"
#include "fuzz_bag.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dloam::fuzz::expect_input_error_or_success([&] {
    auto file =
        dloam::io::bag_detail::open_mcap_memory(std::vector<std::uint8_t>(data, data + size), "fuzz.mcap");
    dloam::fuzz::read_bag_file(*file);
  });
  return 0;
}
