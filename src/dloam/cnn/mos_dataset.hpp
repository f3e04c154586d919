// Training data of the moving-object CNN: SemanticKITTI-layout sequences (velodyne/, labels/,
// poses.txt [+ calib.txt]) turned into range image bags exactly as the pipeline builds them online
// (vertical-angle correction, de-skew with the inter-scan motion, projection, eq. 13 speed images),
// with per-pixel targets. Frames are prepared once and kept compact in memory; a sample is a bag
// drawn on demand, with the poses of the past scans perturbed (the pipeline's own poses are not
// exact) and optional mirroring. No LibTorch here.
#pragma once

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "dloam/core/range_image_bag.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam::cnn {

inline constexpr std::uint8_t kTargetStatic = 0, kTargetMoving = 1, kTargetIgnore = 255;

/// One prepared scan.
struct MosFrame {
  RangeImage image;                  ///< projection of `points` (one point per valid pixel)
  std::vector<Vec3> points;          ///< the nearest point of each valid pixel, de-skewed
  std::vector<float> intensity;      ///< per entry of `points`
  std::vector<std::uint8_t> target;  ///< rows*cols: kTargetStatic / kTargetMoving / kTargetIgnore
  Pose pose = Pose::Identity();      ///< ground-truth world pose
};

struct MosSequence {
  std::string dir;
  std::vector<MosFrame> frames;
  double weight = 1.0;  ///< training draws per frame and epoch (MosSource::weight)
  SensorConfig sensor;  ///< the sensor model the frames were prepared with (their speed images too)
};

/// Where a training sequence's scans, labels and poses come from.
struct MosSource {
  std::string dir;  ///< the scans: a sequence folder or a recording
  /// Empty: `dir`'s own labels/ and poses.txt (annotated or simulated drives). Otherwise the output
  /// folder of `dloam run --clean` on `dir`: labels from its clean/labels/, poses from its poses.txt
  /// (with its calib.txt), i.e. a real drive labelled by the whole-drive pass, without annotation.
  std::string run_dir;
  double weight = 1.0;  ///< each frame is drawn `weight` times per epoch on average (> 0)
  std::string config;   ///< YAML config (file or shipped name) of this drive's sensor; empty: the command's
};

/// Parses "DIR[,run=RUN_DIR][,weight=W][,config=FILE]" (throws InputError naming the spec on a bad
/// key or value).
MosSource parse_mos_source(const std::string& spec);

struct PoseNoise {
  double rotation_deg = 0.05;   ///< sigma per axis, on each past scan's pose relative to the current
  double translation_m = 0.03;  ///< sigma per axis
};

/// Reads and prepares every scan of a labelled sequence with ground-truth poses (throws InputError
/// naming the folder when labels or poses are missing). `progress(done, total)` is optional.
MosSequence load_mos_sequence(const std::string& dir, const SensorConfig& sensor,
                              const std::function<void(std::size_t, std::size_t)>& progress = {});
/// The same for any source: with a run folder, a missing poses.txt or label file is an InputError
/// naming it.
MosSequence load_mos_sequence(const MosSource& source, const SensorConfig& sensor,
                              const std::function<void(std::size_t, std::size_t)>& progress = {});

/// The bag of frame `k` with `m` speed images (past scans k-1..k-m, fewer at the start), past poses
/// perturbed by `noise` drawn from `rng` (no noise when rng is null), with the sequence's sensor.
RangeImageBag sample_bag(const MosSequence& seq, std::size_t k, int m, const PoseNoise& noise,
                         std::mt19937* rng);

}  // namespace dloam::cnn
