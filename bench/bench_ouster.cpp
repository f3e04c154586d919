// Speed of the Ouster decoder on real packets: the 64 packets of the OS-2-128 recording (one
// 1024 x 128 frame, RNG19_RFL8_SIG16_NIR16), fed again and again with the frame id advanced, so
// every iteration decodes one whole frame (0.1 s of sensor time at 1024x10) into points.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench_main.hpp"
#include "dloam/drivers/ouster.hpp"
#include "dloam/io/pcap.hpp"

namespace {

using namespace dloam;
using namespace dloam::drivers;

const std::string kBase = std::string(DLOAM_SENSORS_DIR) + "/ouster/";

struct Stream {
  OusterMetadata md;
  std::vector<std::vector<std::uint8_t>> packets;  ///< lidar packets of one frame
};

Stream load(const std::string& pcap, const std::string& json) {
  Stream s;
  s.md = load_ouster_metadata(kBase + json);
  io::PcapReader reader(kBase + pcap);
  io::UdpDatagram d;
  const OusterPacketFormat format(s.md);
  while (reader.next(d))
    if (d.payload.size() == format.packet_size) s.packets.push_back(d.payload);
  return s;
}

void decode_frames(benchmark::State& state, const std::string& pcap, const std::string& json,
                   ReturnMode mode) {
  Stream s = load(pcap, json);
  DriverOptions options;
  options.scan.returns = mode;
  OusterScanner scanner(s.md, options);
  const bool legacy = s.md.profile == OusterProfile::kLegacy;
  const OusterPacketFormat& f = scanner.format();
  std::vector<Scan> done;
  std::uint32_t frame = 0;
  std::size_t points = 0;
  for (auto _ : state) {
    ++frame;
    for (auto& p : s.packets) {
      if (legacy) {
        for (int c = 0; c < f.columns_per_packet; ++c) {
          std::uint8_t* col = p.data() + f.packet_header_size + static_cast<std::size_t>(c) * f.column_size;
          col[10] = static_cast<std::uint8_t>(frame);
          col[11] = static_cast<std::uint8_t>(frame >> 8);
        }
      } else {
        p[2] = static_cast<std::uint8_t>(frame);
        p[3] = static_cast<std::uint8_t>(frame >> 8);
      }
      Packet packet;
      packet.data = p.data();
      packet.size = p.size();
      scanner.add(packet, done);
    }
    for (const auto& scan : done) points += scan.size();
    done.clear();
  }
  state.counters["points/frame"] =
      benchmark::Counter(static_cast<double>(points) / static_cast<double>(state.iterations()));
  // Real time of a frame / decoding time of a frame.
  state.counters["x_real_time"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / s.md.fps, benchmark::Counter::kIsRate);
}

void BM_OusterOS2_128_Single(benchmark::State& state) {
  decode_frames(state, "OS-2-128-U1_v2.3.0_1024x10.pcap", "OS-2-128-U1_v2.3.0_1024x10.json",
                ReturnMode::kStrongest);
}
void BM_OusterOS0_32_DualAll(benchmark::State& state) {
  decode_frames(state, "OS-0-32-U1_v2.2.0_1024x10.pcap", "OS-0-32-U1_v2.2.0_1024x10.json", ReturnMode::kAll);
}
void BM_OusterOS0_128_LowDataRate(benchmark::State& state) {
  decode_frames(state, "OS-0-128-U1_v2.3.0_1024x10.pcap", "OS-0-128-U1_v2.3.0_1024x10.json",
                ReturnMode::kStrongest);
}

}  // namespace

BENCHMARK(BM_OusterOS2_128_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OusterOS0_32_DualAll)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OusterOS0_128_LowDataRate)->Unit(benchmark::kMillisecond);
DLOAM_BENCHMARK_MAIN()
