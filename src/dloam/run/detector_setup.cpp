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

std::shared_ptr<MovingSegmenter> prepare_detector(PipelineConfig& config, std::string* note) {
  DetectionConfig& detection = config.detection;
#ifdef DLOAM_WITH_TORCH
  std::string dir;
  if (detection.model_path.empty() && detection.detector == Detector::kCnn) dir = io::data_dir() + "/models";
  if (detection.model_path.empty() && detection.detector == Detector::kAuto) {
    dir = io::model_dir();
    if (dir.empty()) {  // no shipped model to be found: what a build without LibTorch does
      detection.detector = Detector::kGeometric;
      if (note)
        *note =
            "no dloam data folder with the shipped model was found (set DLOAM_DATA_DIR): "
            "detector auto uses the geometric detector";
      return nullptr;
    }
  }
  return cnn::prepare_detector(detection, dir, config.sensor, note);
#else
  CnnModelInfo none;
  none.missing_reason = "this dloam was built without LibTorch (DLOAM_WITH_TORCH=OFF)";
  try {
    const DetectorChoice choice = choose_detector(detection.detector, none, config.sensor);
    detection.detector = choice.detector;
    if (note) *note = choice.note;
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  return nullptr;
#endif
}

}  // namespace dloam::run
