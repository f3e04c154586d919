#include "dloam/run/detector_setup.hpp"

#include <stdexcept>

#include "dloam/core/types.hpp"
#include "dloam/io/data_dir.hpp"
#include "dloam/pipeline/detector_choice.hpp"
#ifdef DLOAM_WITH_TORCH
#include "dloam/cnn/cnn_segmenter.hpp"
#endif

namespace dloam::run {

bool has_cnn() {
#ifdef DLOAM_WITH_TORCH
  return true;
#else
  return false;
#endif
}

namespace {

/// Resolves the detector when no model can be loaded (`why` says why), through choose_detector as
/// every other path: auto is the geometric detector, cnn an error. `tell` adds a note for auto.
std::shared_ptr<MovingSegmenter> without_model(DetectionConfig& detection, const SensorConfig& sensor,
                                               const std::string& platform, const std::string& why, bool tell,
                                               std::string* note) {
  CnnModelInfo none;
  none.missing_reason = why;
  try {
    const DetectorChoice choice = choose_detector(detection.detector, none, sensor, platform);
    detection.detector = choice.detector;
    if (note)
      *note = tell && choice.note.empty() ? why + ": detector auto uses the geometric detector" : choice.note;
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  return nullptr;
}

}  // namespace

std::shared_ptr<MovingSegmenter> prepare_detector(PipelineConfig& config, std::string* note) {
  DetectionConfig& detection = config.detection;
  if (detection.detector != Detector::kAuto && detection.detector != Detector::kCnn) return nullptr;
#ifdef DLOAM_WITH_TORCH
  std::string dir;
  if (detection.model_path.empty() && detection.detector == Detector::kCnn) dir = io::data_dir() + "/models";
  if (detection.model_path.empty() && detection.detector == Detector::kAuto) {
    dir = io::model_dir();
    if (dir.empty())
      return without_model(detection, config.sensor, config.motion.platform,
                           "no dloam data folder with the shipped model was found (set DLOAM_DATA_DIR)", true,
                           note);
  }
  return cnn::prepare_detector(detection, dir, config.sensor, config.motion.platform, note);
#else
  return without_model(detection, config.sensor, config.motion.platform,
                       "this dloam was built without LibTorch (DLOAM_WITH_TORCH=OFF)", false, note);
#endif
}

}  // namespace dloam::run
