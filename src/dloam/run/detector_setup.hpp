// What every front-end does before it builds the Pipeline: resolve detection.detector (auto) with
// choose_detector against the CNN model (detection.model_path, else models/mos_m<m>.pt in the data
// folder, see io/data_dir.hpp) and load the model when the CNN is used. Without LibTorch no model
// is available: auto is the geometric detector and cnn an error.
#pragma once

#include <memory>
#include <string>

#include "dloam/core/moving_segmenter.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam::run {

/// True when this dloam was built with LibTorch (DLOAM_WITH_TORCH): the CNN detector exists.
bool has_cnn();

/// Resolves the detector and the model path in `config` (written back, so that config.yaml records
/// what ran) and returns the loaded segmenter when the detector is cnn (null otherwise). `note`
/// receives a line for the user when the choice needs one. Throws InputError for a missing or bad
/// model file, or cnn without LibTorch.
std::shared_ptr<MovingSegmenter> prepare_detector(PipelineConfig& config, std::string* note = nullptr);

}  // namespace dloam::run
