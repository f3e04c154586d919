#include "dloam/pipeline/step_fit.hpp"

#include <algorithm>

#include "dloam/core/speed_matrix.hpp"

namespace dloam {

std::vector<int> probe_pixels(const SegmentationResult& seg, const std::vector<Vec3>& points) {
  const std::size_t stride = std::max<std::size_t>(1, seg.image.range.size() / kProbePixels);
  return static_area_pixels(seg.image, points, seg.pixel_label, static_cast<int>(stride));
}

double step_fit(const SegmentationResult& seg, const std::vector<Vec3>& points, const std::vector<int>& probe,
                const Pose& step, const std::vector<float>& previous_range, const SensorConfig& sensor,
                double tolerance) {
  return static_fit(seg.image, points, probe, step, previous_range, sensor, tolerance).fraction();
}

}  // namespace dloam
