// Cost of the dynamic-object detection pieces on two real HDL-64E scans (kitti-raw-0005, scans
// 10 and 11): object extraction (PCA, eqs. 8-11), pre-registration (T_coarse), the speed matrix
// (eq. 13) and the cluster detector, and the whole DynamicStage as the pipeline calls it.
#include <benchmark/benchmark.h>

#include "bench_main.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/dynamic_stage.hpp"

using namespace dloam;

namespace {

struct Data {
  PipelineConfig cfg;
  std::vector<Vec3> raw[2];
  std::vector<double> times[2];
  SegmentationResult seg[2];
  Pose motion = Pose::Identity();
};

const Data& data() {
  static const Data d = [] {
    Data x;
    x.cfg = io::default_config("HDL-64E");  // as config/kitti-raw.yaml
    x.cfg.sensor.vertical_angle_correction_deg = 0.22;
    x.cfg.detection.detector = Detector::kGeometric;
    const io::Sequence seq = io::open_sequence(DLOAM_KITTI_0005);
    const auto poses = seq.lidar_poses();
    x.motion = poses[10].inverse() * poses[11];
    for (int k = 0; k < 2; ++k) {
      const PointCloud c = seq.read_scan(10 + static_cast<std::size_t>(k));
      x.raw[k] = c.xyz;
      correct_vertical_angle(x.raw[k], x.cfg.sensor.vertical_angle_correction_deg);
      x.times[k] = point_times(c, false);
      x.seg[k] = segment(deskew(x.raw[k], x.times[k], x.motion), x.cfg.sensor, x.cfg.segmentation);
    }
    return x;
  }();
  return d;
}

/// The step prior the pipeline gives the dynamic stage: the car preset's gate over one sweep.
StepPrior prior(const Pose& predicted) {
  const PipelineConfig cfg;
  StepPrior p;
  p.predicted = predicted;
  p.gate = MotionModel(cfg.motion).gate(p.interval.dt);
  p.search_range = cfg.motion.max_speed * p.interval.dt;
  p.yaw_range = cfg.motion.max_angular_speed_deg * M_PI / 180.0 * p.interval.dt;
  return p;
}

void BM_ExtractObjects(benchmark::State& st) {
  const Data& d = data();
  const auto pts = deskew(d.raw[1], d.times[1], d.motion);
  for (auto _ : st) benchmark::DoNotOptimize(extract_objects(pts, d.seg[1], d.cfg.preregistration));
}

void BM_CoarseMotion(benchmark::State& st) {
  const Data& d = data();
  const ObjectSet prev =
      extract_objects(deskew(d.raw[0], d.times[0], d.motion), d.seg[0], d.cfg.preregistration);
  const ObjectSet cur =
      extract_objects(deskew(d.raw[1], d.times[1], d.motion), d.seg[1], d.cfg.preregistration);
  FeatureMap target;
  target.edges.build(prev.poles);
  target.planes.build(prev.planes);
  for (auto _ : st)
    benchmark::DoNotOptimize(coarse_motion(cur, target, d.motion, d.cfg.preregistration, nullptr));
}

void BM_SpeedMatrixAndDetector(benchmark::State& st) {
  const Data& d = data();
  const auto cur = deskew(d.raw[1], d.times[1], d.motion);
  for (auto _ : st) {
    const SpeedMatrix S =
        compute_speed_matrix(d.seg[1].image, cur, d.motion, d.seg[0].image.range, d.cfg.sensor);
    benchmark::DoNotOptimize(detect_dynamic(d.seg[1], S, d.cfg.detection));
  }
}

void BM_DeskewScan(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) benchmark::DoNotOptimize(deskew(d.raw[1], d.times[1], d.motion));
}

void BM_SpeedMatrix(benchmark::State& st) {
  const Data& d = data();
  const auto cur = deskew(d.raw[1], d.times[1], d.motion);
  for (auto _ : st)
    benchmark::DoNotOptimize(
        compute_speed_matrix(d.seg[1].image, cur, d.motion, d.seg[0].image.range, d.cfg.sensor));
}

/// One scan in the steady state (the first pair, with its one-time search, is done outside the timing).
void BM_DynamicStage(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    st.PauseTiming();
    DynamicStage stage(d.cfg);
    stage.process(d.raw[0], d.times[0], deskew(d.raw[0], d.times[0], d.motion), d.seg[0], prior(d.motion));
    stage.process(d.raw[1], d.times[1], deskew(d.raw[1], d.times[1], d.motion), d.seg[1], prior(d.motion));
    auto next = deskew(d.raw[0], d.times[0], d.motion.inverse());
    st.ResumeTiming();
    // Scan 10 again after scan 11: a drive backwards, the same work as a new scan.
    benchmark::DoNotOptimize(
        stage.process(d.raw[0], d.times[0], std::move(next), d.seg[0], prior(d.motion.inverse())));
  }
}

/// The first pair: no motion prior, the forward search and both scans de-skewed with its result.
void BM_DynamicStageFirstPair(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    st.PauseTiming();
    DynamicStage stage(d.cfg);
    stage.process(d.raw[0], d.times[0], d.raw[0], d.seg[0], prior(Pose::Identity()));
    st.ResumeTiming();
    benchmark::DoNotOptimize(
        stage.process(d.raw[1], d.times[1], d.raw[1], d.seg[1], prior(Pose::Identity())));
  }
}

}  // namespace

BENCHMARK(BM_ExtractObjects)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CoarseMotion)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpeedMatrixAndDetector)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeskewScan)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpeedMatrix)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DynamicStage)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DynamicStageFirstPair)->Unit(benchmark::kMillisecond);
DLOAM_BENCHMARK_MAIN()
