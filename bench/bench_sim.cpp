// Simulator throughput: one rolling-shutter sweep of each scenario with an HDL-64E (64 x 2048 rays)
// and a VLP-16, and world generation. Counters: points per scan.
#include <benchmark/benchmark.h>

#include <memory>

#include "bench_main.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"

using namespace dloam;
using namespace dloam::sim;

namespace {
void BM_Sweep(benchmark::State& state, ScenarioKind kind, const char* preset) {
  ScenarioParams p;
  p.kind = kind;
  p.frames = 200;
  LidarOptions o;
  o.sensor = sensor_preset(preset);
  p.max_range = o.sensor.max_range;
  Simulator sim(make_world(p), o);
  int frame = 0;
  std::size_t points = 0;
  for (auto _ : state) {
    const SimFrame f = sim.frame(frame);
    frame = (frame + 1) % p.frames;
    points += f.scan.cloud.size();
    benchmark::DoNotOptimize(f.scan.cloud.xyz.data());
  }
  state.counters["points_per_scan"] = static_cast<double>(points) / static_cast<double>(state.iterations());
  state.counters["actors"] = static_cast<double>(sim.world().actors.size());
}

void BM_MakeWorld(benchmark::State& state, ScenarioKind kind) {
  ScenarioParams p;
  p.kind = kind;
  p.frames = 1000;
  for (auto _ : state) {
    const World w = make_world(p);
    benchmark::DoNotOptimize(w.static_mesh.triangles.data());
    state.counters["triangles"] = static_cast<double>(w.static_mesh.size());
  }
}
}  // namespace

BENCHMARK_CAPTURE(BM_Sweep, urban_hdl64, ScenarioKind::Urban, "HDL-64E")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, highway_hdl64, ScenarioKind::Highway, "HDL-64E")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, loop_hdl64, ScenarioKind::Loop, "HDL-64E")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, urban_vlp16, ScenarioKind::Urban, "VLP-16")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MakeWorld, urban_1000_frames, ScenarioKind::Urban)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MakeWorld, loop_1000_frames, ScenarioKind::Loop)->Unit(benchmark::kMillisecond);

DLOAM_BENCHMARK_MAIN()
