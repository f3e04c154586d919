// dloam::PointCloud (+ labels) -> sensor_msgs/PointCloud2 (see pointcloud2.hpp).
#include <sensor_msgs/PointField.h>

#include <cstring>

#include "dloam/ros/pointcloud2.hpp"

namespace dloam::ros1 {

namespace {
void add_field(sensor_msgs::PointCloud2& msg, const char* name, std::uint8_t type) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = msg.point_step;
  f.datatype = type;
  f.count = 1;
  msg.fields.push_back(f);
  msg.point_step += 4;  // every field written here is 4 bytes
}
}  // namespace

sensor_msgs::PointCloud2 to_pointcloud2(const PointCloud& cloud, const std::vector<Label>& labels) {
  if (!labels.empty() && labels.size() != cloud.size())
    throw std::invalid_argument("to_pointcloud2: labels and cloud differ in size");
  sensor_msgs::PointCloud2 msg;
  for (const char* axis : {"x", "y", "z"}) add_field(msg, axis, sensor_msgs::PointField::FLOAT32);
  const bool with_i = cloud.has_intensity(), with_t = cloud.has_time(), with_l = !labels.empty();
  if (with_i) add_field(msg, "intensity", sensor_msgs::PointField::FLOAT32);
  if (with_t) add_field(msg, "time", sensor_msgs::PointField::FLOAT32);
  if (with_l) add_field(msg, "label", sensor_msgs::PointField::UINT32);
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(cloud.size());
  msg.row_step = msg.width * msg.point_step;
  msg.is_bigendian = false;
  msg.is_dense = true;
  msg.data.resize(static_cast<std::size_t>(msg.row_step));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    std::uint8_t* record = msg.data.data() + i * msg.point_step;
    std::uint32_t offset = 0;
    auto next = [&](auto value) {  // fields in the order add_field() declared them
      std::memcpy(record + offset, &value, sizeof(value));
      offset += 4;
    };
    for (int a = 0; a < 3; ++a) next(static_cast<float>(cloud.xyz[i][a]));
    if (with_i) next(cloud.intensity[i]);
    if (with_t) next(cloud.time[i]);
    if (with_l) next(static_cast<std::uint32_t>(labels[i]));
  }
  return msg;
}

}  // namespace dloam::ros1
