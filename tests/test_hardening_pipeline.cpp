// The pipeline on unusual input: an exception inside the mapping worker, a vehicle standing still
// with a moving-object detector, and scans without enough points to register.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "sim_test_util.hpp"

using namespace dloam;
using ::testing::HasSubstr;

namespace {
sim::Simulator simulator(int frames) {
  return test::make_simulator(sim::ScenarioKind::Urban, frames, 3, sensor_preset("VLP-16"));
}

PipelineConfig vlp16(const std::string& detector) {
  PipelineConfig cfg = io::default_config("VLP-16");
  cfg.detection.detector = *enum_from_name<Detector>(detector);
  return cfg;
}
}  // namespace

TEST(HardeningPipeline, AnExceptionInTheMappingWorkerIsAnErrorNotAnAbort) {
  // A leaf far too small for the voxel keys (validation refuses it; the pipeline itself must
  // still fail cleanly): voxel_downsample throws inside the worker thread.
  PipelineConfig cfg = vlp16("none");
  cfg.mapping.edge_leaf_size = 1e-9;
  sim::Simulator sim = simulator(4);
  std::string message;
  {
    Pipeline pipeline(cfg);
    try {
      for (int k = 0; k < 4; ++k) (void)pipeline.process(sim.frame(k).scan.cloud);
      (void)pipeline.trajectory();
    } catch (const InputError& e) {
      message = e.what();
    }
    EXPECT_THAT(message, HasSubstr("mapping of scan"));
    EXPECT_THAT(message, HasSubstr("voxel"));
    // The failed job is gone: the accessors and the destructor do not join it again.
    EXPECT_NO_THROW((void)pipeline.trajectory());
    EXPECT_NO_THROW((void)pipeline.global_map());
  }
}

TEST(HardeningPipeline, AStationaryVehicleWithADetectorStillMapsTheScene) {
  sim::Simulator sim = simulator(1);
  const PointCloud scan = sim.frame(0).scan.cloud;
  std::size_t none_points = 0;
  for (const std::string detector : {"none", "geometric"}) {
    Pipeline pipeline(vlp16(detector));
    for (int k = 0; k < 4; ++k) (void)pipeline.process(scan);  // the same scan: no motion at all
    const std::size_t points = pipeline.global_map().size();
    if (detector == "none") none_points = points;
    EXPECT_GT(points, none_points / 2) << detector;  // the detector keeps the static scene
    EXPECT_GT(points, 1000u) << detector;
    for (const Pose& p : pipeline.trajectory()) EXPECT_LT(p.translation().norm(), 0.01) << detector;
  }
}

TEST(HardeningPipeline, AScanWithoutPointsToRegisterIsFlaggedDegenerate) {
  sim::Simulator sim = simulator(4);
  Pipeline pipeline(vlp16("none"));
  for (int k = 0; k < 3; ++k) (void)pipeline.process(sim.frame(k).scan.cloud);
  PointCloud one;
  one.xyz.emplace_back(10.0, 0.0, 0.0);
  one.intensity.push_back(0.5f);
  const ScanResult r = pipeline.process(one);
  EXPECT_TRUE(r.degenerate);
  EXPECT_LT(r.n_edges + r.n_planes, 2u);
  EXPECT_NO_THROW((void)pipeline.process(sim.frame(3).scan.cloud));
}
