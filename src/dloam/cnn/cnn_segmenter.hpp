// The trained MosNet (mos_net.hpp) as the pipeline's MovingSegmenter: LibTorch inference on the
// CPU. This header does not include LibTorch, so front-ends can use it cheaply.
#pragma once

#include <memory>
#include <string>

#include "dloam/core/moving_segmenter.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam::cnn {

/// Loads a model written by `dloam train` (throws InputError naming the file when it is missing or
/// not a model, or when `expected_m` >= 0 differs from the model's m). `threads`: column parts of
/// the range image run in parallel (forward_in_parts); LibTorch itself runs on one thread.
std::unique_ptr<MovingSegmenter> load_cnn_segmenter(const std::string& model_path, int threads,
                                                    int expected_m = -1);

/// detection.model_path, or `<model_dir>/mos_m<m>.pt` (the model shipped with dloam) when empty.
std::string resolve_model_path(const DetectionConfig& detection, const std::string& model_dir);

/// Front-end setup of the detector: resolves detector auto (choose_detector, with the model file's
/// training size and the platform) and an empty model_path (the shipped model) in `detection`, and loads the
/// segmenter when the detector is cnn (null otherwise). `note` (if given) receives the choice's
/// line for the user. Throws InputError for a missing or bad model file when cnn is asked for.
/// Front-ends call dloam/run/detector_setup.hpp, which finds `model_dir` in the data folder.
std::shared_ptr<MovingSegmenter> prepare_detector(DetectionConfig& detection, const std::string& model_dir,
                                                  const SensorConfig& sensor, const std::string& platform,
                                                  std::string* note = nullptr);

}  // namespace dloam::cnn
