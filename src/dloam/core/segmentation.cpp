// Segmentation module: projection + ground + clustering, labels back-projected to points.
#include "dloam/core/segmentation.hpp"

#include <stdexcept>

#include "dloam/core/ground.hpp"

namespace dloam {

SegmentationResult segment(const std::vector<Vec3>& points, const SensorConfig& sensor,
                           const SegmentationConfig& config) {
  try {
    sensor.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("segment: ") + e.what());
  }
  return segment_image(points, project(points, sensor), sensor, config);
}

SegmentationResult segment_image(const std::vector<Vec3>& points, RangeImage image,
                                 const SensorConfig& sensor, const SegmentationConfig& config) {
  if (image.rows != sensor.N_scan || image.cols != sensor.Horizon_SCAN ||
      image.row_of_point.size() != points.size())
    throw InputError("segment: range image (" + std::to_string(image.rows) + "x" +
                     std::to_string(image.cols) + ", " + std::to_string(image.row_of_point.size()) +
                     " points) does not match the sensor (" + std::to_string(sensor.N_scan) + "x" +
                     std::to_string(sensor.Horizon_SCAN) + ") and " + std::to_string(points.size()) +
                     " points");
  SegmentationResult out;
  const GroundResult ground = extract_ground(points, image, sensor, config);
  ClusterResult clusters = cluster_range_image(image, ground.mask, sensor, config);
  out.pixel_label = std::move(clusters.label);
  out.num_clusters = clusters.num_clusters;
  out.num_ground_pixels = ground.num_ground;
  out.ground_normal = ground.normal;
  out.ground_height = ground.height;
  out.ground_plane_valid = ground.plane_valid;
  out.point_label.assign(points.size(), kOutlierLabel);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int px = image.pixel_of_point(i);
    if (px >= 0) out.point_label[i] = out.pixel_label[static_cast<std::size_t>(px)];
  }
  out.image = std::move(image);
  return out;
}

}  // namespace dloam
