// Cost of the CNN detector's pieces on real HDL-64E scans (kitti-raw-0005, scans 10-16): the range
// image bag of scan 16 with the default m speed images (eq. 13 against the scans before it), the
// MosNet forward pass of the shipped model (LibTorch, CPU; in DLOAM_TORCH_THREADS column parts in
// parallel, default detection.threads), and the object-level decision.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "bench_main.hpp"
#include "dloam/cnn/cnn_segmenter.hpp"
#include "dloam/cnn/mos_net.hpp"
#include "dloam/core/cnn_decision.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"

using namespace dloam;

namespace {

struct Data {
  PipelineConfig cfg;
  std::vector<Vec3> points;
  SegmentationResult seg;
  std::vector<float> intensity;
  Pose pose;
  std::unique_ptr<ScanHistory> history;
  std::unique_ptr<MovingSegmenter> net;
};

Data& data() {
  static Data d = [] {
    Data x;
    x.cfg = io::default_config("HDL-64E");
    x.cfg.sensor.vertical_angle_correction_deg = 0.22;
    const io::Sequence seq = io::open_sequence(DLOAM_KITTI_0005);
    const auto poses = seq.lidar_poses();
    const int m = x.cfg.detection.m;
    x.history = std::make_unique<ScanHistory>(m, x.cfg.sensor);
    for (std::size_t k = 16 - static_cast<std::size_t>(m); k <= 16; ++k) {
      const PointCloud c = seq.read_scan(k);
      std::vector<Vec3> pts = c.xyz;
      correct_vertical_angle(pts, x.cfg.sensor.vertical_angle_correction_deg);
      pts = deskew(pts, point_times(c, false), poses[k - 1].inverse() * poses[k]);
      if (k < 16) {
        x.history->push(project(pts, x.cfg.sensor).range, poses[k]);
      } else {
        x.seg = segment(pts, x.cfg.sensor, x.cfg.segmentation);
        x.points = std::move(pts);
        x.intensity = c.intensity;
        x.pose = poses[k];
      }
    }
    // Timing does not depend on the weights: the shipped model when present, else a fresh one.
    std::string model = std::string(DLOAM_SOURCE_DIR) + "/models/mos_m" + std::to_string(m) + ".pt";
    if (!std::filesystem::exists(model)) {
      model = (std::filesystem::temp_directory_path() / ("bench_cnn_m" + std::to_string(m) + ".pt")).string();
      cnn::MosNet fresh(cnn::MosNetOptions{m, 8});
      cnn::save_mos_net(fresh, model);
    }
    const char* threads = std::getenv("DLOAM_TORCH_THREADS");
    x.net = cnn::load_cnn_segmenter(model, threads ? std::atoi(threads) : x.cfg.detection.threads, m);
    return x;
  }();
  return d;
}

void BM_RangeImageBag(benchmark::State& st) {
  Data& d = data();
  for (auto _ : st) benchmark::DoNotOptimize(d.history->bag(d.seg.image, d.points, d.intensity, d.pose));
}

void BM_CnnForward(benchmark::State& st) {
  Data& d = data();
  const RangeImageBag bag = d.history->bag(d.seg.image, d.points, d.intensity, d.pose);
  for (int i = 0; i < 3; ++i) d.net->moving_probability(bag);  // warm-up
  for (auto _ : st) benchmark::DoNotOptimize(d.net->moving_probability(bag));
}

void BM_CnnDecision(benchmark::State& st) {
  Data& d = data();
  const auto prob = d.net->moving_probability(d.history->bag(d.seg.image, d.points, d.intensity, d.pose));
  for (auto _ : st) {
    const DetectionResult det = decide_from_probability(d.seg, prob, d.cfg.detection);
    benchmark::DoNotOptimize(point_labels(d.seg, det));
  }
}

}  // namespace

BENCHMARK(BM_RangeImageBag)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CnnForward)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CnnDecision)->Unit(benchmark::kMillisecond);
DLOAM_BENCHMARK_MAIN()
