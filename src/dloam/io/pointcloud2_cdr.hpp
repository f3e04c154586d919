// sensor_msgs/msg/PointCloud2 of ROS 2 bags in CDR: decoding to a CloudView (then
// convert_cloud(), pointcloud2_fields.hpp) and encoding dloam clouds for the bag writers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/pointcloud2_fields.hpp"

namespace dloam::io {

inline constexpr const char* kPointCloud2Type = "sensor_msgs/msg/PointCloud2";

struct PointCloud2Message {
  double stamp = 0.0;  ///< header stamp (s)
  std::string frame_id;
  CloudView view;  ///< points into the message buffer
};

/// Decodes a CDR PointCloud2; throws InputError "<where>: ..." for a short or damaged message.
PointCloud2Message parse_pointcloud2(const std::uint8_t* data, std::size_t size, const std::string& where);

/// Decodes and converts (convert_cloud()) in one step.
ConvertedCloud read_pointcloud2(const std::uint8_t* data, std::size_t size, const std::string& where,
                                double* stamp = nullptr);

/// A CDR PointCloud2 of float32 x y z, intensity (when the cloud has it) and time (float32 sweep
/// fraction, when it has it), height 1, little-endian, is_dense.
std::vector<std::uint8_t> encode_pointcloud2(const PointCloud& cloud, double stamp,
                                             const std::string& frame_id);

/// The message definition (ros2msg, with the types it uses) for MCAP schema records.
const std::string& pointcloud2_definition();

}  // namespace dloam::io
