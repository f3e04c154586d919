// sensor_msgs/PointCloud2 <-> dloam::PointCloud. Reading is io::convert_cloud()'s (shared with
// the ROS 2 bags, see dloam/io/pointcloud2_fields.hpp): x y z (float32 or float64), optional
// intensity (any numeric type) and optional per-point time as the LiDAR drivers write it;
// times become sweep fractions in [0, 1) like the PCD reader's. Writes clouds with x y z
// intensity and an optional uint32 `label` field (for the ROS node).
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/pointcloud2_fields.hpp"

namespace dloam::ros1 {

using ConvertedCloud = io::ConvertedCloud;

/// Converts one message; `where` names it in errors ("drive.bag: topic /points, message 12").
/// The errors and the handling of non-finite points are io::convert_cloud()'s.
ConvertedCloud from_pointcloud2(const sensor_msgs::PointCloud2& msg, const std::string& where);

/// A PointCloud2 with float32 x y z, intensity (when the cloud has it), time (float32 sweep
/// fraction, when it has it) and uint32 `label` (when `labels` is not empty; same size as the cloud).
sensor_msgs::PointCloud2 to_pointcloud2(const PointCloud& cloud, const std::vector<Label>& labels = {});

}  // namespace dloam::ros1
