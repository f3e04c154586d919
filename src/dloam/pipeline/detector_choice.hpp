// The one decision of which moving-object detector a run uses: detection.detector `auto` is the
// CNN when a model is available, was trained on range images of this sensor's size and the
// platform is a car (the shipped model learnt from car drives; on handheld and legged walks the
// geometric detector tracks more steps, docs/tracking.md), else the geometric detector. Every
// front-end (dloam run, the ROS node, the Python module, the Pipeline given a segmenter) resolves
// `auto` with this function.
#pragma once

#include <string>

#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam {

/// What is known of the CNN model a run could use.
struct CnnModelInfo {
  bool available = false;  ///< a model can be loaded (the file exists and dloam has LibTorch)
  std::string path;        ///< for messages
  /// Range-image size it was trained on; 0: unknown (any size is taken to fit).
  int trained_rows = 0, trained_cols = 0;
  /// Why no model is available (e.g. "this dloam was built without LibTorch"), for messages.
  std::string missing_reason;
};

struct DetectorChoice {
  Detector detector = Detector::kGeometric;  ///< never kAuto
  /// A line for the user when the choice deserves one: why `auto` took the geometric detector
  /// although a model exists, or a warning when `cnn` was asked for a model of another size.
  std::string note;
};

/// Resolves `requested` (kAuto included) against `model`, the sensor and the platform
/// (motion.platform: car, handheld, legged). Throws std::invalid_argument when kCnn is requested
/// and no model is available.
DetectorChoice choose_detector(Detector requested, const CnnModelInfo& model, const SensorConfig& sensor,
                               const std::string& platform);

}  // namespace dloam
