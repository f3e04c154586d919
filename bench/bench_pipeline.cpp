// Per-module benchmarks of the odometry path and the mapping on real HDL-64E scans
// (../shared/data/kitti-raw-0005): de-skew, segmentation, features, scan-to-scan odometry,
// scan-to-map mapping, and the whole pipeline per scan.
//   build/bench/bench_pipeline --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <filesystem>

#include "bench_main.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/mapping.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"

using namespace dloam;

namespace {

constexpr std::size_t kScans = 20;

struct Data {
  PipelineConfig cfg;
  std::vector<PointCloud> clouds;
  std::vector<std::vector<Vec3>> points;  // vertical-angle corrected
  std::vector<SegmentationResult> segs;
  std::vector<FeatureSet> features;
  std::vector<Pose> gt;  // LiDAR frame
};

const Data& data() {
  static const Data d = [] {
    Data out;
    out.cfg = io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml");
    const auto seq = io::open_sequence(DLOAM_KITTI_0005);
    const auto gt = seq.lidar_poses();
    for (std::size_t i = 0; i < kScans; ++i) {
      out.clouds.push_back(seq.read_scan(i));
      auto pts = out.clouds.back().xyz;
      correct_vertical_angle(pts, out.cfg.sensor.vertical_angle_correction_deg);
      out.segs.push_back(segment(pts, out.cfg.sensor, out.cfg.segmentation));
      out.features.push_back(extract_features(pts, out.segs.back(), out.cfg.features));
      out.points.push_back(std::move(pts));
      out.gt.push_back(gt[i]);
    }
    return out;
  }();
  return d;
}

void BM_Deskew(benchmark::State& state) {
  const auto& d = data();
  const auto times = point_times(d.clouds[1], false);
  const Pose motion = d.gt[0].inverse() * d.gt[1];
  for (auto _ : state) benchmark::DoNotOptimize(deskew(d.points[1], times, motion));
}

void BM_Segmentation(benchmark::State& state) {
  const auto& d = data();
  std::size_t i = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(segment(d.points[i++ % kScans], d.cfg.sensor, d.cfg.segmentation));
}

void BM_Features(benchmark::State& state) {
  const auto& d = data();
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % kScans;
    benchmark::DoNotOptimize(extract_features(d.points[k], d.segs[k], d.cfg.features));
  }
}

void BM_Odometry(benchmark::State& state) {
  const auto& d = data();
  std::size_t i = 0;
  ScanToScanOdometry odo(d.cfg.odometry);
  for (auto _ : state) {
    const auto& f = d.features[i++ % kScans];
    benchmark::DoNotOptimize(odo.process({f.f_e, f.f_p, {}, {}}, f.F_e, f.F_p, Pose::Identity()));
  }
}

void BM_Mapping(benchmark::State& state) {
  // Mapping of the 20 scans from their reference poses, the map growing as in a run.
  const auto& d = data();
  for (auto _ : state) {
    Mapper mapper(d.cfg.mapping);
    for (std::size_t k = 0; k < kScans; ++k) {
      const auto& f = d.features[k];
      benchmark::DoNotOptimize(mapper.process(k, {f.F_e, f.F_p, {}, {}}, d.gt[k]));
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kScans));
}

void BM_PipelinePerScan(benchmark::State& state) {
  const auto& d = data();
  for (auto _ : state) {
    Pipeline pipeline(d.cfg);
    for (std::size_t k = 0; k < kScans; ++k) benchmark::DoNotOptimize(pipeline.process(d.clouds[k]));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kScans));
}

}  // namespace

BENCHMARK(BM_Deskew)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Segmentation)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Features)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Odometry)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Mapping)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PipelinePerScan)->Unit(benchmark::kMillisecond);
DLOAM_BENCHMARK_MAIN()
