// Odometry report shared by `dloam eval odometry` and `dloam run`: the readable table and the JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dloam/eval/odometry_metrics.hpp"

namespace dloam::app {

/// Segment options: the given lengths (every frame a start unless `step` > 0), else the devkit's
/// 100..800 m every 10 frames, or 5,10,20,30 m every frame when the path is shorter than 200 m.
eval::SegmentOptions segment_options(const std::vector<Pose>& gt, const std::vector<double>& lengths,
                                     std::size_t step = 0);

void print_odometry(const eval::OdometryResult& r, const std::string& frame);
nlohmann::json odometry_json(const eval::OdometryResult& r, const eval::SegmentOptions& options,
                             const std::string& frame);

/// Evaluates, prints the table and writes `json_path` (used by `dloam run` with ground truth).
void write_odometry_metrics(const std::string& json_path, const std::vector<Pose>& gt,
                            const std::vector<Pose>& est, const std::vector<double>& lengths);

}  // namespace dloam::app
