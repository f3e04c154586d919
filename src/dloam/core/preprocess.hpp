// Scan preprocessing before the pipeline proper: the intrinsic vertical-angle correction of a
// sensor (KITTI's HDL-64E scans are known to need about +0.22 deg) applied to the points.
#pragma once

#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

/// Rotates every point's elevation by `degrees` about the sensor origin (azimuth and range kept).
void correct_vertical_angle(std::vector<Vec3>& points, double degrees);

}  // namespace dloam
