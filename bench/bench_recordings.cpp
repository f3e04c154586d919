// Speed of reading recordings end to end, as `dloam run` does: io::open_sequence() (the container,
// the vendor scanner over every packet with outlines only: the indexing pass) and then read_scan()
// of every scan in order (the points decoded, one session); also the container alone and the
// indexing pass alone. Reports the recording's duration (first to last packet) over the CPU time as
// `x_realtime` (one core), on the 128-beam recordings of the sensors folder and the VLP-16 capture.
// These recordings hold 1-3 rotations (50 for the VLP-16), so the per-open costs (the scanner made
// from the calibration, an Ouster scanner's xyz lookup table) weigh more than in a long recording.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "bench_main.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/packet_sequence.hpp"

namespace {

using namespace dloam;
namespace fs = std::filesystem;

const std::string kSensors = DLOAM_SENSORS_DIR;

/// A nebula model folder -> its bag folder; a capture stays as it is.
std::string resolve(const std::string& rel) {
  const std::string path = kSensors + "/" + rel;
  if (!fs::is_directory(path) || fs::exists(path + "/metadata.yaml")) return path;
  for (const auto& e : fs::directory_iterator(path))
    if (e.is_directory()) return e.path().string();
  return path;
}

std::shared_ptr<io::PacketRecording> packets_of(const std::string& path) {
  if (fs::is_directory(path)) {
    auto bag = std::make_shared<const io::Bag>(path);
    const auto& t = bag->topics().at(0);
    return io::bag_packet_recording(bag, t.name, t.type);
  }
  return io::pcap_recording(path, path.find("ouster") != std::string::npos ? 7502 : 2368);
}

/// First to last packet stamp of the recording's data stream.
double duration(const std::string& path) {
  auto stream = packets_of(path)->open();
  drivers::Packet p;
  double first = -1.0, last = 0.0;
  while (stream->next(p)) {
    if (first < 0) first = p.stamp;
    last = p.stamp;
  }
  return last - first;
}

enum class Phase { kContainer, kIndex, kAll };

/// kContainer: every packet read from the file (no decoding); kIndex: open_sequence() (the
/// indexing pass); kAll: open_sequence() and read_scan() of every scan.
void read_recording(benchmark::State& state, const std::string& rel, Phase phase) {
  const std::string path = resolve(rel);
  if (!fs::exists(path)) {
    state.SkipWithError("no sensors data");
    return;
  }
  const double seconds = duration(path);
  std::size_t points = 0, scans = 0;
  for (auto _ : state) {
    if (phase == Phase::kContainer) {
      auto stream = packets_of(path)->open();
      drivers::Packet p;
      while (stream->next(p)) points += p.size;
      continue;
    }
    const io::Sequence seq = io::open_sequence(path);
    scans += seq.size();
    if (phase == Phase::kAll)
      for (std::size_t i = 0; i < seq.size(); ++i) points += seq.read_scan(i).size();
  }
  state.counters["x_realtime"] =
      benchmark::Counter(seconds * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["scans"] = static_cast<double>(scans) / static_cast<double>(state.iterations());
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
}

#define DLOAM_RECORDING(name, rel)                                                         \
  BENCHMARK_CAPTURE(read_recording, name##_container, std::string(rel), Phase::kContainer) \
      ->Unit(benchmark::kMillisecond);                                                     \
  BENCHMARK_CAPTURE(read_recording, name##_index, std::string(rel), Phase::kIndex)         \
      ->Unit(benchmark::kMillisecond);                                                     \
  BENCHMARK_CAPTURE(read_recording, name##_all, std::string(rel), Phase::kAll)->Unit(benchmark::kMillisecond)

DLOAM_RECORDING(vls128_db3, "velodyne/nebula/vls128");
DLOAM_RECORDING(qt128_db3, "hesai/nebula/qt128");
DLOAM_RECORDING(os2_128_pcap, "ouster/OS-2-128-U1_v2.3.0_1024x10.pcap");
DLOAM_RECORDING(os1_128_pcap, "ouster/OS-1-128_v2.3.0_1024x10_lb_n3.pcap");
DLOAM_RECORDING(os0_128_pcap, "ouster/OS-0-128-U1_v2.3.0_1024x10.pcap");
DLOAM_RECORDING(vlp16_pcap, "velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap");

}  // namespace

DLOAM_BENCHMARK_MAIN()
