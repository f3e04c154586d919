// A whole run of the pipeline over a sequence (a folder or a recording, io::open_sequence), written
// to an output folder (run_outputs.hpp): what `dloam run` and the Python module's run() do.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dloam/core/moving_segmenter.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/run_outputs.hpp"

namespace dloam::run {

struct RunOptions {
  std::string out;  ///< output folder
  std::size_t first = 0;
  std::optional<std::size_t> count;  ///< scans from `first`; empty: to the end
  /// Delete the points the ground-truth labels mark moving before the pipeline sees them (a perfect
  /// detector's reference); the written labels mark them moving. Needs labels/.
  bool drop_labelled_moving = false;
  std::vector<double> lengths;  ///< segment lengths of metrics.json
  /// Called after each scan with the number done and the total (progress display).
  std::function<void(std::size_t done, std::size_t total, const ScanResult& result)> on_scan;
  /// Called with what the caller should show (a degenerate scan).
  std::function<void(const std::string& warning)> on_warning;
  /// Called after the sensor model was checked against the first scans and before anything is
  /// written into `out` (e.g. to lock the folder or clear an earlier run's outputs).
  std::function<void()> before_output;
  /// Checked before each scan: when it returns true, the run stops and still writes complete outputs.
  std::function<bool()> stop;
};

struct SequenceRun {
  RunSummary summary;
  bool stopped = false;  ///< `stop` ended the run early
  /// The error that ended the run early (a bad scan, a failure in the pipeline); the outputs of the
  /// scans before it are written. Empty when the run went to its end.
  std::string error;
};

/// Runs scans [first, first + count) of `sequence` through a Pipeline of `config` (its detector
/// resolved: prepare_detector; `cnn` the segmenter it returned) and writes the output folder
/// (RunOutputs): poses in the frame of the input's poses.txt (camera frame when calib.txt has Tr),
/// labels named after the scan files, metrics against the ground truth when it has poses / labels.
/// Throws InputError, before anything is written, for a first scan out of range, missing labels
/// for drop_labelled_moving, or first scans that mostly miss the sensor model's field of view (the
/// wrong sensor model, SensorFitCheck); and when the first scan of the run fails (nothing is kept).
SequenceRun run_sequence(const io::Sequence& sequence, const PipelineConfig& config,
                         std::shared_ptr<MovingSegmenter> cnn, const RunOptions& options);

/// The scan without the points the ground truth labels moving (a perfect detector's input, for
/// studies); `kept`: the input index of each remaining point.
PointCloud without_moving(const PointCloud& cloud, const std::vector<Label>& gt,
                          std::vector<std::size_t>& kept);
/// A result of the reduced scan in the input's point indices; the dropped points are labelled moving.
void restore_indices(ScanResult& r, const std::vector<std::size_t>& kept, std::size_t input_size);

}  // namespace dloam::run
