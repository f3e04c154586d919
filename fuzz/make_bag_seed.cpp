// Writes the seed bag of the rosbag harness: the first points of a KITTI scan as a few
// sensor_msgs/PointCloud2 messages (float32 x y z intensity, a float32 per-point time).
//   make_bag_seed SCAN.bin OUT.bag [POINTS]
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "dloam/io/kitti.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_bag_seed SCAN.bin OUT.bag [POINTS]\n");
    return 2;
  }
  try {
    const dloam::PointCloud scan = dloam::io::read_kitti_bin(argv[1]);
    const std::size_t n =
        std::min<std::size_t>(scan.size(), argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 48);
    rosbag::Bag bag(argv[2], rosbag::bagmode::Write);
    for (int k = 0; k < 3; ++k) {
      sensor_msgs::PointCloud2 msg;
      msg.header.stamp.fromSec(1317000000.0 + 0.1 * k);
      msg.header.frame_id = "velodyne";
      msg.height = 1;
      msg.width = static_cast<std::uint32_t>(n);
      msg.point_step = 20;
      msg.row_step = msg.point_step * msg.width;
      msg.is_dense = k != 1;
      const char* names[] = {"x", "y", "z", "intensity", "time"};
      for (std::uint32_t f = 0; f < 5; ++f) {
        sensor_msgs::PointField field;
        field.name = names[f];
        field.offset = 4 * f;
        field.datatype = sensor_msgs::PointField::FLOAT32;
        field.count = 1;
        msg.fields.push_back(field);
      }
      msg.data.resize(msg.row_step);
      for (std::size_t i = 0; i < n; ++i) {
        const float v[5] = {static_cast<float>(scan.xyz[i].x()), static_cast<float>(scan.xyz[i].y()),
                            static_cast<float>(scan.xyz[i].z()), scan.intensity[i],
                            static_cast<float>(0.1 * static_cast<double>(i) / static_cast<double>(n))};
        std::memcpy(msg.data.data() + 20 * i, v, sizeof(v));
      }
      bag.write("/velodyne_points", msg.header.stamp, msg);
    }
    bag.close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_bag_seed: %s\n", e.what());
    return 1;
  }
  return 0;
}
