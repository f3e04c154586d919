// libFuzzer harness: pcap / pcapng captures through libpcap (from memory): record headers, link
// types, IPv4 / IPv6 / VLAN decoding, fragment reassembly, the statistics line.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dloam/io/pcap.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dloam::fuzz::expect_input_error_or_success([&] {
    dloam::io::PcapOptions options;
    options.max_pending_fragments = 4;
    auto reader = dloam::io::PcapReader::from_memory(std::vector<std::uint8_t>(data, data + size),
                                                     "fuzz.pcap", options);
    dloam::io::UdpDatagram datagram;
    for (int k = 0; k < 256 && reader->next(datagram); ++k) {
      if (datagram.payload.size() > size) __builtin_trap();  // a datagram is never larger than the file
    }
    (void)reader->stats().describe();
  });
  // The frame decoder alone, on every link type the reader knows.
  for (const int dlt : {1, 12, 101, 113, 276, 0}) {
    const auto frame = dloam::io::pcap_detail::decode_frame(dlt, data, size);
    if (frame.payload && (frame.payload < data || frame.payload + frame.size > data + size)) __builtin_trap();
  }
  return 0;
}
