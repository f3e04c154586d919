// sensor_msgs/PointCloud2 <-> dloam::PointCloud. Reads x y z (float32 or float64), optional
// intensity (any numeric type) and optional per-point time as the LiDAR drivers write it:
// `time` float32 seconds (Velodyne), `t` uint32 nanoseconds (Ouster), `timestamp` float64
// seconds (Hesai); times become sweep fractions in [0, 1) like the PCD reader's. Writes clouds
// with x y z intensity and an optional uint32 `label` field (for the ROS node).
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <cstddef>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::ros1 {

struct ConvertedCloud {
  PointCloud cloud;
  std::size_t dropped = 0;  ///< NaN/Inf points of an is_dense=false message (no returns), removed
};

/// Converts one message; `where` names it in errors ("drive.bag: topic /points, message 12").
/// Throws dloam::InputError for: no points, big-endian data, a missing x/y/z field, a field of
/// an unsupported datatype or outside the point record, data shorter than the header announces,
/// a NaN/Inf coordinate in a message that declares is_dense, a message with no finite point.
/// Non-finite points of an is_dense=false message (organised clouds mark no-return pixels so)
/// are removed and counted in `dropped`; the point order of the others is kept.
ConvertedCloud from_pointcloud2(const sensor_msgs::PointCloud2& msg, const std::string& where);

/// A PointCloud2 with float32 x y z, intensity (when the cloud has it), time (float32 sweep
/// fraction, when it has it) and uint32 `label` (when `labels` is not empty; same size as the cloud).
sensor_msgs::PointCloud2 to_pointcloud2(const PointCloud& cloud, const std::vector<Label>& labels = {});

}  // namespace dloam::ros1
