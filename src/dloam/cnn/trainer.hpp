// `dloam train`: supervised training of MosNet on range image bags (mos_dataset.hpp) with
// class weighting for the rare moving class (weighted BCE + a soft-IoU term on the moving class),
// augmentation (random column crops, mirroring, intensity scaling, pose noise on the past scans),
// a validation split (the last frames of every sequence, never trained on) scored with the moving
// IoU per epoch, and checkpointing (best and last model). Deterministic for a seed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "dloam/cnn/mos_dataset.hpp"

namespace dloam::cnn {

struct TrainOptions {
  int m = 6;
  int width = 8;  ///< MosNet width (channels of the first level)
  int epochs = 30;
  int batch = 4;
  int crop_cols = 512;          ///< training crops (columns); validation uses full scans
  double learning_rate = 2e-3;  ///< Adam, cosine decay to 5 % over the epochs
  double weight_decay = 1e-4;
  double val_fraction = 0.2;  ///< last fraction of every sequence held out
  int val_stride = 2;         ///< every n-th validation frame is scored
  PoseNoise pose_noise;
  unsigned seed = 1;
  int threads = 2;
  std::string out = "model.pt";  ///< best model; "<out>.last" is the latest epoch, "<out>.csv" the log
};

struct EpochReport {
  int epoch = 0;
  double train_loss = 0.0;
  double val_iou = 0.0, val_precision = 0.0, val_recall = 0.0;
  double seconds = 0.0;
  bool best = false;
};

struct TrainCallbacks {
  std::function<void(int epoch, std::size_t step, std::size_t steps, double loss)> on_step;
  std::function<void(const EpochReport&)> on_epoch;
};

/// Trains on the prepared sequences (each with its own sensor model; all of `sensor`'s range-image
/// size, which the model records); returns the per-epoch reports. Throws std::invalid_argument
/// for unusable options (no training frames, no moving pixel in the training split, ...).
std::vector<EpochReport> train_mos_net(const std::vector<MosSequence>& data, const SensorConfig& sensor,
                                       const TrainOptions& options, const TrainCallbacks& callbacks = {});

}  // namespace dloam::cnn
