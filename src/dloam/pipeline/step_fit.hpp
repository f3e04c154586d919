// How well a step brings a scan onto the previous scan's surfaces: the fraction of the surface of
// static-looking cluster pixels (a subsample, grazing surfaces left out) whose range agrees with the
// previous scan's range image within kProbeInlier after moving them by the step. The pipeline's step
// check scores predictions, searched steps and the odometry with it; the detection checks T_coarse
// with it before it trusts a speed matrix.
#pragma once

#include <vector>

#include "dloam/core/segmentation.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// A probe pixel fits the previous scan when its range lies this close to the previous ranges (m).
constexpr double kProbeInlier = 0.2;
/// Pixels of the range image per probe pixel sampled (before keeping cluster pixels only).
constexpr std::size_t kProbePixels = 12000;

/// The probe pixels of a segmented scan: every (size / kProbePixels)-th pixel of a cluster whose
/// surface is not seen at grazing incidence.
std::vector<int> probe_pixels(const SegmentationResult& seg, const std::vector<Vec3>& points);

/// The fraction of the probe's surface within `tolerance` of `previous_range` once moved by `step`
/// (current -> previous frame); 0 when nothing lands on a previous return.
double step_fit(const SegmentationResult& seg, const std::vector<Vec3>& points, const std::vector<int>& probe,
                const Pose& step, const std::vector<float>& previous_range, const SensorConfig& sensor,
                double tolerance = kProbeInlier);

}  // namespace dloam
