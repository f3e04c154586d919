// Speed of the Hesai decoder on the nebula recordings of the shared sensors folder: every packet
// of a bag decoded into scans, per iteration, by a scanner made for it. Counters: packets/s,
// points/s, and x_realtime = the stream's duration (its packets' sensor-time span plus one packet
// interval) / decoding time (CPU). The bags hold 0.2-0.4 s, so these include the first scans'
// allocations; QT128_replayed_x10 decodes the QT128 bag (exactly 2 turns) 10 times in a row with
// its sequence numbers, times and tail CRCs continued: a 2 s stream, 20 scans.
// One thread: `bench_hesai --benchmark_filter=QT128`.
#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "dloam/drivers/hesai.hpp"
#include "dloam/drivers/hesai_packet.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"

namespace {

using namespace dloam;
using namespace dloam::drivers;

struct Stream {
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<double> stamps;
  double duration = 0.0;  // s of sensor time
};

const Stream& stream(const std::string& folder, hesai::Model model) {
  static std::map<std::string, Stream> cache;
  auto it = cache.find(folder);
  if (it != cache.end()) return it->second;
  Stream s;
  const std::string dir = std::string(DLOAM_SENSORS_DIR) + "/hesai/nebula/" + folder;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (!e.is_directory()) continue;
    const io::Bag bag(e.path().string());
    const std::string topic = "/pandar_packets";
    for (std::size_t k = 0; k < bag.message_count(topic); ++k) {
      const std::vector<std::uint8_t> data = bag.read(topic, k);
      const io::PacketMessage m =
          io::decode_packet_message("pandar_msgs/msg/PandarScan", data.data(), data.size(),
                                    1e-9 * bag.message_time_ns(topic, k), bag.where(topic, k));
      for (const io::PacketSlice& p : m.packets) {
        s.bytes.emplace_back(data.begin() + static_cast<std::ptrdiff_t>(p.offset),
                             data.begin() + static_cast<std::ptrdiff_t>(p.offset + p.size));
        s.stamps.push_back(p.stamp);
      }
    }
  }
  if (s.bytes.size() >= 2) {
    auto time_of = [&](std::size_t i) {
      Packet p;
      p.data = s.bytes[i].data();
      p.size = s.bytes[i].size();
      return hesai::parse_packet(p, model).sensor_time;
    };
    const double span = time_of(s.bytes.size() - 1) - time_of(0);
    s.duration = span * static_cast<double>(s.bytes.size()) / static_cast<double>(s.bytes.size() - 1);
  }
  return cache.emplace(folder, std::move(s)).first->second;
}

// The QT128 bag `copies` times, copy k moved on by k x its duration: UDP sequence, date and time,
// tail CRC (tail = 12 + 2 x 514 + 4 + 17 bytes in), recording stamps.
const Stream& replayed_qt128(int copies) {
  static std::map<int, Stream> cache;
  auto it = cache.find(copies);
  if (it != cache.end()) return it->second;
  const Stream& one = stream("qt128", hesai::Model::kPandarQT128);
  Stream s;
  const std::size_t tail = 12 + 2 * 514 + 4 + 17;
  for (int k = 0; k < copies; ++k)
    for (std::size_t i = 0; i < one.bytes.size(); ++i) {
      std::vector<std::uint8_t> b = one.bytes[i];
      Packet p;
      p.data = b.data();
      p.size = b.size();
      const hesai::PacketView v = hesai::parse_packet(p, hesai::Model::kPandarQT128);
      const double t = v.sensor_time + k * one.duration;
      const auto secs = static_cast<std::time_t>(std::floor(t));
      const auto micros = static_cast<std::uint32_t>(std::lround((t - std::floor(t)) * 1e6)) % 1000000u;
      std::tm tm{};
      gmtime_r(&secs, &tm);
      const std::uint8_t date[6] = {
          static_cast<std::uint8_t>(tm.tm_year), static_cast<std::uint8_t>(tm.tm_mon + 1),
          static_cast<std::uint8_t>(tm.tm_mday), static_cast<std::uint8_t>(tm.tm_hour),
          static_cast<std::uint8_t>(tm.tm_min),  static_cast<std::uint8_t>(tm.tm_sec)};
      std::copy(date, date + 6, b.begin() + static_cast<std::ptrdiff_t>(tail + 15));
      const std::uint32_t seq = v.sequence + static_cast<std::uint32_t>(k * one.bytes.size());
      for (int j = 0; j < 4; ++j) {
        b[tail + 21 + static_cast<std::size_t>(j)] = static_cast<std::uint8_t>(micros >> (8 * j));
        b[tail + 26 + static_cast<std::size_t>(j)] = static_cast<std::uint8_t>(seq >> (8 * j));
      }
      const std::uint32_t crc = hesai::crc32_mpeg2(b.data() + tail, 30);
      for (int j = 0; j < 4; ++j)
        b[tail + 30 + static_cast<std::size_t>(j)] = static_cast<std::uint8_t>(crc >> (8 * j));
      s.bytes.push_back(std::move(b));
      s.stamps.push_back(one.stamps[i] + k * one.duration);
    }
  s.duration = one.duration * copies;
  return cache.emplace(copies, std::move(s)).first->second;
}

void run(benchmark::State& state, const Stream& s, hesai::Model model, ReturnMode returns) {
  if (s.bytes.empty()) {
    state.SkipWithError("no recording");
    return;
  }
  ScannerOptions options;
  options.returns = returns;
  std::size_t points = 0, complete = 0;
  std::string summary;
  for (auto _ : state) {
    complete = 0;
    // As a consumer does: each scan is taken when it is complete and released after use.
    HesaiScanner scanner(model, hesai::nominal_calibration(model), options);
    std::vector<Scan> done;
    points = 0;
    auto consume = [&] {
      for (const Scan& scan : done) {
        points += scan.size();
        complete += scan.complete ? 1 : 0;
      }
      benchmark::DoNotOptimize(done.data());
      done.clear();
    };
    for (std::size_t i = 0; i < s.bytes.size(); ++i) {
      Packet p;
      p.data = s.bytes[i].data();
      p.size = s.bytes[i].size();
      p.stamp = s.stamps[i];
      scanner.add(p, done);
      if (!done.empty()) consume();
    }
    scanner.finish(done);
    consume();
    summary = scanner.describe();
  }
  state.SetLabel(std::to_string(complete) + " complete scans; " + summary.substr(summary.find("; ") + 2));
  const auto n = static_cast<double>(state.iterations());
  state.counters["packets/s"] =
      benchmark::Counter(n * static_cast<double>(s.bytes.size()), benchmark::Counter::kIsRate);
  state.counters["points/s"] =
      benchmark::Counter(n * static_cast<double>(points), benchmark::Counter::kIsRate);
  // seconds of stream per second of decoding
  state.counters["x_realtime"] = benchmark::Counter(n * s.duration, benchmark::Counter::kIsRate);
}

void BM_Hesai(benchmark::State& state, const char* folder, hesai::Model model, ReturnMode returns) {
  run(state, stream(folder, model), model, returns);
}

void BM_HesaiReplayed(benchmark::State& state, int copies, ReturnMode returns) {
  run(state, replayed_qt128(copies), hesai::Model::kPandarQT128, returns);
}

BENCHMARK_CAPTURE(BM_Hesai, QT128_all, "qt128", hesai::Model::kPandarQT128, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, QT128_strongest, "qt128", hesai::Model::kPandarQT128, ReturnMode::kStrongest)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HesaiReplayed, QT128_replayed_x10_all, 10, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HesaiReplayed, QT128_replayed_x10_strongest, 10, ReturnMode::kStrongest)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, Pandar40P_all, "40p", hesai::Model::kPandar40P, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, Pandar64_all, "64", hesai::Model::kPandar64, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, QT64_all, "qt64", hesai::Model::kPandarQT64, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, XT16_all, "xt16", hesai::Model::kPandarXT16, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, XT32_all, "xt32", hesai::Model::kPandarXT32, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hesai, XT32M_all, "xt32m", hesai::Model::kPandarXT32M, ReturnMode::kAll)
    ->Unit(benchmark::kMillisecond);

}  // namespace

DLOAM_BENCHMARK_MAIN()
