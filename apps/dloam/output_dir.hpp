// The output folder of `dloam run`: locked against a second run writing into it at the same time,
// and holding only this run's outputs (an earlier run's are refused unless --overwrite, which
// deletes them first), so that the files in it always belong together.
#pragma once

#include <string>

namespace dloam::app {

class OutputDir {
 public:
  /// Creates `dir` and locks it; throws InputError naming it when another process holds the lock,
  /// when it is `input_dir` or a sequence folder (velodyne/), or when it holds outputs of an
  /// earlier run and `overwrite` is false. With `overwrite`, deletes those outputs (only the files
  /// `dloam run` writes: poses.txt, poses_tum.txt, poses_gt.txt, calib.txt, map.ply, moving.ply,
  /// timing.csv, config.yaml, metrics.json, report.html, labels/*.label and their .tmp files).
  OutputDir(const std::string& dir, const std::string& input_dir, bool overwrite);
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  [[nodiscard]] const std::string& path() const { return dir_; }

 private:
  std::string dir_;
  int lock_fd_ = -1;
};

}  // namespace dloam::app
