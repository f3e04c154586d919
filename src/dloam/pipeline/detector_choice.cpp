#include "dloam/pipeline/detector_choice.hpp"

#include <stdexcept>

namespace dloam {

DetectorChoice choose_detector(Detector requested, const CnnModelInfo& model, const SensorConfig& sensor,
                               const std::string& platform) {
  DetectorChoice out;
  std::string mismatch;  // the model's training image size when it is not this sensor's
  if (model.available && model.trained_rows > 0 &&
      (model.trained_rows != sensor.N_scan || model.trained_cols != sensor.Horizon_SCAN))
    mismatch = model.path + " was trained on " + std::to_string(model.trained_rows) + " x " +
               std::to_string(model.trained_cols) + " range images, this sensor gives " +
               std::to_string(sensor.N_scan) + " x " + std::to_string(sensor.Horizon_SCAN);
  switch (requested) {
    case Detector::kAuto: {
      const bool car = platform == "car";  // the shipped model learnt from car drives
      out.detector = model.available && mismatch.empty() && car ? Detector::kCnn : Detector::kGeometric;
      if (!mismatch.empty())
        out.note = mismatch + ": detector auto uses the geometric detector";
      else if (model.available && !car)
        out.note = "detector auto uses the geometric detector on a " + platform +
                   " platform (the CNN learnt from car drives; --detector cnn to use it)";
      break;
    }
    case Detector::kCnn:
      if (!model.available)
        throw std::invalid_argument(
            "detection.detector is cnn but no model can be loaded" +
            (model.missing_reason.empty() ? std::string() : " (" + model.missing_reason + ")"));
      out.detector = Detector::kCnn;
      if (!mismatch.empty())
        out.note = "warning: " + mismatch + "; its moving-object segmentation may be poor";
      break;
    default:
      out.detector = requested;
  }
  return out;
}

}  // namespace dloam
