// libFuzzer harness: the vendor packet decoders (Velodyne, Ouster, Hesai) through the registry.
// Input: packets, each a 2-byte little-endian length and its bytes. The decoder is the one that
// claims the first packets, as for a recording; Ouster packets need the sensor's metadata, taken
// from $DLOAM_FUZZ_OUSTER_METADATA when it is set.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "dloam/drivers/registry.hpp"
#include "dloam/drivers/scanner.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<dloam::drivers::Packet> packets;
  for (std::size_t at = 0; at + 2 <= size && packets.size() < 64;) {
    const std::size_t n = std::min<std::size_t>(data[at] | (data[at + 1] << 8), size - at - 2);
    dloam::drivers::Packet p;
    p.data = data + at + 2;
    p.size = n;
    p.stamp = 1.0 + 1e-4 * static_cast<double>(packets.size());
    p.where = "fuzz: packet " + std::to_string(packets.size());
    packets.push_back(p);
    at += 2 + n;
  }
  if (packets.empty()) return 0;
  dloam::fuzz::expect_input_error_or_success([&] {
    dloam::drivers::DriverOptions options;
    if (dloam::drivers::identify(packets) == dloam::drivers::Vendor::kOuster) {
      const char* metadata = std::getenv("DLOAM_FUZZ_OUSTER_METADATA");
      if (!metadata) return;
      options.calibration = metadata;
    }
    const std::vector<dloam::drivers::Packet> first(
        packets.begin(), packets.begin() + std::min<std::size_t>(4, packets.size()));
    auto scanner = dloam::drivers::make_scanner(options, first);
    std::vector<dloam::drivers::Scan> done;
    for (const auto& p : packets) {
      dloam::fuzz::expect_input_error_or_success([&] { scanner->add(p, done); });
    }
    scanner->finish(done);
    for (const auto& scan : done) {
      if (scan.intensity.size() != scan.size() || scan.ring.size() != scan.size()) __builtin_trap();
      for (const auto& p : scan.xyz)
        if (!p.allFinite()) __builtin_trap();  // a decoded return is a finite point
    }
    (void)scanner->sensor();
    (void)scanner->describe();
  });
  return 0;
}
