// The report of a run folder (run/run_outputs.hpp) as one self-contained HTML page: the plots are
// gnuplot PNGs embedded as data URIs, the tables are HTML. Written by `dloam report RUN_DIR` and
// `dloam run --report`:
//   - trajectory, top view: the estimate coloured by its position error against the ground truth
//     (both anchored at the first scan), the ground truth beside it (when poses_gt.txt is there);
//   - relative error (KITTI devkit) per segment length, from metrics.json;
//   - the global map from above, coloured by height, with the points labelled moving marked;
//   - the time of each pipeline module per scan, from timing.csv;
//   - tables: odometry, moving-object segmentation (MOS), map and tracking figures, configuration.
// Each plot is a <figure class="plot" id="..."> (trajectory, relative-error, map, timing).
#pragma once

#include <string>

namespace dloam::app {

/// Reads the run folder and writes the page atomically; throws InputError naming a missing or bad
/// file (poses.txt, timing.csv and config.yaml are required; the others are optional) or when
/// gnuplot is missing.
void write_html_report(const std::string& run_dir, const std::string& html_path);

}  // namespace dloam::app
