// sensor_msgs/PointCloud2 -> dloam::PointCloud (see pointcloud2.hpp): the message's layout as an
// io::CloudView, converted by the ROS-free reader shared with the ROS 2 bags.
#include "dloam/ros/pointcloud2.hpp"

namespace dloam::ros1 {

ConvertedCloud from_pointcloud2(const sensor_msgs::PointCloud2& msg, const std::string& where) {
  io::CloudView view;
  view.height = msg.height;
  view.width = msg.width;
  view.point_step = msg.point_step;
  view.row_step = msg.row_step;
  view.is_bigendian = msg.is_bigendian != 0;
  view.is_dense = msg.is_dense != 0;
  view.data = msg.data.data();
  view.size = msg.data.size();
  view.fields.reserve(msg.fields.size());
  for (const auto& f : msg.fields) view.fields.push_back({f.name, f.offset, f.datatype, f.count});
  return io::convert_cloud(view, where);
}

}  // namespace dloam::ros1
