// Gnuplot script for an odometry report: the top view of both trajectories (equal axes) and bars
// of the devkit relative errors per segment length. The data are embedded as gnuplot datablocks,
// so the script is self-contained; the caller writes it to a file and runs `gnuplot` on it.
#pragma once

#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/eval/relative_error.hpp"

namespace dloam::eval {

struct PlotOptions {
  std::string png_path;               ///< output image
  std::string terminal = "pngcairo";  ///< gnuplot terminal: "pngcairo" or "png"
  int horizontal_axis = 0;            ///< position component drawn left-right (0 = x)
  int vertical_axis = 1;              ///< position component drawn bottom-top (1 = y, 2 = z)
  std::string title = "dloam odometry";
};

/// The whole gnuplot script. Throws InputError if an axis is not 0, 1 or 2 or png_path is empty.
std::string odometry_plot_script(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const std::vector<LengthError>& per_length, const PlotOptions& options);

}  // namespace dloam::eval
