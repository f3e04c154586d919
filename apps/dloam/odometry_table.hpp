// The readable tables of the evaluations, shared by `dloam eval` and `dloam run`.
#pragma once

#include <string>

#include "dloam/eval/mos_metrics.hpp"
#include "dloam/eval/odometry_metrics.hpp"

namespace dloam::app {

void print_odometry(const eval::OdometryResult& r, const std::string& frame);
void print_mos(const eval::MosResult& r, double object_threshold = 0.5);

}  // namespace dloam::app
