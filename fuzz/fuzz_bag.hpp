// Shared by the ROS 2 storage harnesses: every topic's index and messages of a storage file,
// each message decoded as what its topic's type says (PointCloud2 or a packet message).
#pragma once

#include <cstddef>
#include <string>

#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "fuzz_util.hpp"

namespace dloam::fuzz {

inline void read_bag_file(io::bag_detail::BagFile& file) {
  (void)file.format();
  for (const auto& topic : file.topics()) {
    const auto refs = file.index(topic.name);
    for (std::size_t k = 0; k < refs.size() && k < 16; ++k) {
      const std::string where = file.path() + ": topic " + topic.name + ", message " + std::to_string(k);
      const auto bytes = file.read(refs[k], where);
      expect_input_error_or_success([&] {
        if (topic.type == io::kPointCloud2Type) {
          (void)io::read_pointcloud2(bytes.data(), bytes.size(), where);
        } else if (io::is_packet_message_type(topic.type)) {
          const auto message = io::decode_packet_message(topic.type, bytes.data(), bytes.size(), 0.0, where);
          for (const auto& p : message.packets)
            if (p.offset + p.size > bytes.size()) __builtin_trap();
        }
      });
    }
  }
}

}  // namespace dloam::fuzz
