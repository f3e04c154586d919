// Speed of the Velodyne decoder: every packet of a recording through the Scanner (decoding,
// corrections, rotation assembly), the packets read once beforehand. Reports the recording's
// duration over the decoding time as `x_realtime` (one core).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "dloam/drivers/velodyne.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"

namespace {

using namespace dloam;

struct Recording {
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<drivers::Packet> packets;
  double duration = 0.0;  ///< first to last packet (TOH), s
};

const Recording& recording(const std::string& folder) {
  static std::map<std::string, Recording> cache;
  auto it = cache.find(folder);
  if (it != cache.end()) return it->second;
  Recording r;
  io::Bag bag(folder);
  const io::BagTopic& topic = bag.topics().at(0);
  for (std::size_t k = 0; k < bag.message_count(topic.name); ++k) {
    const std::vector<std::uint8_t> data = bag.read(topic.name, k);
    const io::PacketMessage m =
        io::decode_packet_message(topic.type, data.data(), data.size(), 0.0, bag.where(topic.name, k));
    for (const io::PacketSlice& s : m.packets)
      r.bytes.emplace_back(data.begin() + static_cast<std::ptrdiff_t>(s.offset),
                           data.begin() + static_cast<std::ptrdiff_t>(s.offset + s.size));
  }
  for (const auto& b : r.bytes) {
    drivers::Packet p;
    p.data = b.data();
    p.size = b.size();
    r.packets.push_back(p);
  }
  auto toh = [](const drivers::Packet& p) { return drivers::velodyne_packet_header(p).toh_us * 1e-6; };
  r.duration = toh(r.packets.back()) - toh(r.packets.front());
  return cache.emplace(folder, std::move(r)).first->second;
}

/// `streaming`: each finished scan is dropped at once, as a consumer that processes scans one by
/// one does (the allocator then reuses their memory); otherwise all scans are kept to the end.
void decode(benchmark::State& state, const std::string& model, const std::string& calibration,
            bool streaming = false) {
  const std::string dir = std::string(DLOAM_SENSORS_DIR) + "/velodyne/nebula/";
  if (!std::filesystem::exists(dir + model)) {
    state.SkipWithError("no sensors data");
    return;
  }
  std::string folder;
  for (const auto& e : std::filesystem::directory_iterator(dir + model))
    if (e.is_directory()) folder = e.path().string();
  const Recording& rec = recording(folder);
  drivers::DriverOptions o;
  o.calibration = dir + "calibration/" + calibration;
  std::size_t points = 0;
  const std::vector<drivers::Packet> first(rec.packets.begin(), rec.packets.begin() + 100);
  for (auto _ : state) {
    state.PauseTiming();  // reading the calibration file is not decoding
    auto scanner = drivers::make_velodyne_scanner(o, first);
    state.ResumeTiming();
    std::vector<drivers::Scan> scans;
    points = 0;
    for (const drivers::Packet& p : rec.packets) {
      scanner->add(p, scans);
      if (streaming) {
        for (const auto& s : scans) points += s.size();
        scans.clear();
      }
    }
    scanner->finish(scans);
    for (const auto& s : scans) points += s.size();
    benchmark::DoNotOptimize(scans.data());
  }
  state.counters["packets"] = static_cast<double>(rec.packets.size());
  state.counters["points"] = static_cast<double>(points);
  state.counters["x_realtime"] =
      benchmark::Counter(rec.duration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_VelodyneVls128(benchmark::State& state) { decode(state, "vls128", "VLS128.yaml"); }
void BM_VelodyneVls128Streaming(benchmark::State& state) { decode(state, "vls128", "VLS128.yaml", true); }
void BM_VelodyneVlp16Dual(benchmark::State& state) { decode(state, "vlp16", "VLP16.yaml"); }
void BM_VelodyneVlp32(benchmark::State& state) { decode(state, "vlp32", "VLP32.yaml"); }

BENCHMARK(BM_VelodyneVls128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VelodyneVls128Streaming)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VelodyneVlp16Dual)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VelodyneVlp32)->Unit(benchmark::kMillisecond);

}  // namespace

DLOAM_BENCHMARK_MAIN()
