// sensor_msgs/PointCloud2 without ROS types: the message's layout (fields, steps, byte order)
// over its data bytes, and its conversion to a dloam::PointCloud. Shared by the ROS 1 reader
// (dloam_ros) and the ROS 2 bag readers (CDR). Reads x y z (float32 or float64), an optional
// `intensity` (any numeric type) and an optional per-point time as the LiDAR drivers write it:
// `time` float32 s (Velodyne), `t` uint32 ns (Ouster), `timestamp` float64 s (Hesai, absolute),
// `time_stamp` uint32 ns (nebula); times become sweep fractions in [0, 1) (to_sweep_fraction).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::io {

/// sensor_msgs/PointField datatypes.
enum class PointFieldType : std::uint8_t {
  kInt8 = 1,
  kUint8 = 2,
  kInt16 = 3,
  kUint16 = 4,
  kInt32 = 5,
  kUint32 = 6,
  kFloat32 = 7,
  kFloat64 = 8,
};

struct CloudField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;  ///< a PointFieldType value (others are rejected when the field is read)
  std::uint32_t count = 1;
};

/// A PointCloud2 message's layout and data (not owned).
struct CloudView {
  std::uint32_t height = 0, width = 0, point_step = 0, row_step = 0;
  std::vector<CloudField> fields;
  bool is_bigendian = false, is_dense = false;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;  ///< bytes at data
};

struct ConvertedCloud {
  PointCloud cloud;
  std::size_t dropped = 0;  ///< NaN/Inf points of an is_dense=false message (no returns), removed
};

/// Converts one message; `where` names it in errors ("drive.bag: topic /points, message 12").
/// Throws dloam::InputError for: no points, a missing x/y/z field, a field of an unsupported
/// datatype or outside the point record, data shorter than the header announces, a NaN/Inf
/// coordinate in a message that declares is_dense, a message with no finite point. Non-finite
/// points of an is_dense=false message (organised clouds mark no-return pixels so) are removed
/// and counted in `dropped`; the point order of the others is kept. Both byte orders are read.
ConvertedCloud convert_cloud(const CloudView& msg, const std::string& where);

}  // namespace dloam::io
