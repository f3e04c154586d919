// The whole-drive pass of `dloam clean` (and `dloam run --clean`): the scans of a sequence with a
// run's poses through the map cleaner, into RUN_DIR/clean/.
#pragma once

#include <string>

#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam::app {

/// `poses`: sensor -> world of scans first, first + 1, ... (the run's trajectory in the LiDAR
/// frame). Writes labels/, map.ply, map.pcd and metrics.json (with ground truth) into `out_dir`,
/// prints a summary. Throws InputError for bad input.
void clean_sequence(const io::Sequence& seq, const std::vector<Pose>& poses, std::size_t first,
                    const PipelineConfig& config, const std::string& out_dir);

/// Scan k of a drive with poses `poses` as the pipeline saw it: vertical-angle corrected and
/// de-skewed (when the config's deskew is on) with the motion of the poses around it, mid-sweep
/// reference. `stamps`: the scans' times (one per pose) or empty (then 1 / scan rate apart).
std::vector<Vec3> drive_scan_points(const PointCloud& cloud, const std::vector<Pose>& poses, std::size_t k,
                                    const std::vector<double>& stamps, const PipelineConfig& config);

/// The run's poses.txt (KITTI, camera frame when the sequence's calib.txt has Tr) as LiDAR poses.
std::vector<Pose> read_run_poses(const std::string& run_dir, const io::Sequence& seq);

}  // namespace dloam::app
