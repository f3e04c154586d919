// libFuzzer harness: the drivers' raw-packet messages of ROS 2 bags in CDR (VelodyneScan,
// PandarScan, NebulaPackets, Ouster PacketMsg). The first byte picks the message type.
#include <cstddef>
#include <cstdint>

#include "dloam/io/packet_messages.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto& types = dloam::io::packet_message_types();
  const std::string& type = types[data[0] % types.size()];
  dloam::fuzz::expect_input_error_or_success([&] {
    const auto message = dloam::io::decode_packet_message(type, data + 1, size - 1, 1.0, "fuzz.msg");
    for (const auto& p : message.packets)
      if (p.offset + p.size > size - 1) __builtin_trap();  // a packet lies inside the message
  });
  return 0;
}
