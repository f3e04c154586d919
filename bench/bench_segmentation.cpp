// Speed of segmentation (projection, ground, clustering) and feature extraction on real
// HDL-64E scans of kitti-raw-0005 (paper budget: well under 15 ms per scan on one core).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/ground.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/smoothness.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/config.hpp"

namespace {

using namespace dloam;

struct Data {
  SensorConfig sensor = sensor_preset("HDL-64E");
  std::vector<std::vector<Vec3>> scans;
};

const Data& data() {
  static const Data d = [] {
    Data out;
    for (int k : {0, 20, 40, 60, 80}) {
      char name[32];
      std::snprintf(name, sizeof(name), "/velodyne/%06d.bin", k);
      PointCloud cloud = io::read_kitti_bin(std::string(DLOAM_KITTI_0005) + name);
      correct_vertical_angle(cloud.xyz, 0.25);  // KITTI's HDL-64E elevation offset
      out.scans.push_back(std::move(cloud.xyz));
    }
    return out;
  }();
  return d;
}

const std::vector<Vec3>& scan(std::size_t i) { return data().scans[i % data().scans.size()]; }

void BM_Project(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(project(scan(i++), data().sensor));
}

void BM_Ground(benchmark::State& state) {
  std::vector<RangeImage> images;
  for (const auto& s : data().scans) images.push_back(project(s, data().sensor));
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % images.size();
    benchmark::DoNotOptimize(extract_ground(scan(k), images[k], data().sensor, SegmentationConfig{}));
  }
}

void BM_Segment(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(segment(scan(i++), data().sensor, SegmentationConfig{}));
}

void BM_Features(benchmark::State& state) {
  std::vector<SegmentationResult> segs;
  for (const auto& s : data().scans) segs.push_back(segment(s, data().sensor, SegmentationConfig{}));
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % segs.size();
    benchmark::DoNotOptimize(extract_features(scan(k), segs[k], FeatureConfig{}));
  }
}

// The whole module chain per scan: what the pipeline pays.
void BM_SegmentAndFeatures(benchmark::State& state) {
  std::size_t i = 0, features = 0;
  for (auto _ : state) {
    const auto& pts = scan(i++);
    const SegmentationResult seg = segment(pts, data().sensor, SegmentationConfig{});
    const FeatureSet fs = extract_features(pts, seg, FeatureConfig{});
    features += fs.F_e.size() + fs.F_p.size();
  }
  state.counters["features/scan"] =
      benchmark::Counter(static_cast<double>(features), benchmark::Counter::kAvgIterations);
}

}  // namespace

BENCHMARK(BM_Project)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ground)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Segment)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Features)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SegmentAndFeatures)->Unit(benchmark::kMillisecond);
DLOAM_BENCHMARK_MAIN()
