// Simulated drives for the tests: a simulator for a scenario with one seed for the world and the
// LiDAR, and the end-point error of an estimated trajectory (or of a pipeline run over a drive).
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"

namespace dloam::test {

/// The drive of `dloam simulate --scenario KIND --frames FRAMES --seed SEED --traffic TRAFFIC
/// --platform PLATFORM` seen by `sensor` (the world depends on `frames`: a test can process only its
/// first scans).
inline sim::Simulator make_simulator(sim::ScenarioKind kind, int frames, std::uint64_t seed,
                                     const SensorConfig& sensor, double traffic = 1.0,
                                     sim::Platform platform = sim::Platform::Car) {
  sim::ScenarioParams params;
  params.kind = kind;
  params.frames = frames;
  params.seed = seed;
  params.traffic = traffic;
  params.platform = platform;
  sim::LidarOptions options;
  options.sensor = sensor;
  options.seed = seed;
  return sim::Simulator(sim::make_world(params), options);
}

/// Error of the estimated motion from the first scan to the last against the true one (the
/// pipeline starts at identity), and the true motion.
struct EndPointError {
  Pose error = Pose::Identity();
  Pose truth = Pose::Identity();
};
inline EndPointError end_point_error(const std::vector<Pose>& est, const std::vector<Pose>& gt) {
  EndPointError e;
  e.truth = gt.front().inverse() * gt.back();
  e.error = est.back().inverse() * e.truth;
  return e;
}

/// Runs `pipeline` over the first `frames` scans of `simulator`; the end-point error.
inline EndPointError track(Pipeline& pipeline, sim::Simulator& simulator, int frames) {
  std::vector<Pose> est, gt;
  for (int k = 0; k < frames; ++k) {
    const sim::SimFrame f = simulator.frame(k);
    est.push_back(pipeline.process(f.scan.cloud).pose);
    gt.push_back(f.pose);
  }
  return end_point_error(est, gt);
}

}  // namespace dloam::test
