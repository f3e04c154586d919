// Runs the dloam pipeline on the first scans of a drive and prints the sensor poses:
//   dloam_example SEQUENCE_DIR [SCANS]
// SEQUENCE_DIR is anything `dloam run` reads (a KITTI / SemanticKITTI folder, PCD files, a bag or a
// capture). The configuration is the shipped config/kitti-raw.yaml (KITTI raw drives' HDL-64E).
#include <cstdio>
#include <exception>
#include <string>

#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SEQUENCE_DIR [SCANS]\n", argv[0]);
    return 2;
  }
  try {
    const std::string dir = argv[1];
    const std::size_t scans = argc > 2 ? std::stoul(argv[2]) : 2;
    // The HDL-64E preset, then the keys of the shipped file (as `dloam run --config kitti-raw`).
    const dloam::PipelineConfig config =
        dloam::io::config_from("HDL-64E", std::string(DLOAM_DATA_DIR) + "/config/kitti-raw.yaml");
    const dloam::io::Sequence sequence =
        dloam::io::open_sequence(dir, dloam::io::input_options(config.input));
    // detection.detector auto: without a CNN model handed over, the geometric detector.
    dloam::Pipeline pipeline(config);
    for (std::size_t i = 0; i < scans && i < sequence.size(); ++i) {
      const dloam::PointCloud cloud = sequence.read_scan(i);
      const dloam::ScanResult r = pipeline.process(cloud);
      std::size_t moving = 0;
      for (const dloam::Label l : r.labels) moving += dloam::semantic::is_moving(l);
      const auto t = r.pose.translation();
      std::printf("scan %zu: x %.3f m, y %.3f m, z %.3f m; %zu points, %zu moving, %.1f ms\n", i, t.x(),
                  t.y(), t.z(), cloud.size(), moving, r.times[dloam::Module::kTotal]);
    }
    // The mapping-refined trajectory, as `dloam run` writes it (sensor frame).
    const auto trajectory = pipeline.trajectory();
    std::printf("trajectory: %zu poses, last at x %.3f m\n", trajectory.size(),
                trajectory.empty() ? 0.0 : trajectory.back().translation().x());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dloam_example: %s\n", e.what());
    return 1;
  }
  return 0;
}
