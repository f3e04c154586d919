// rosbag input: a bag of sensor_msgs/PointCloud2 messages as a dloam sequence, so every command
// that takes a sequence folder takes a bag. ROS-free header (the ROS types stay in the .cpp).
#pragma once

#include <string>
#include <vector>

#include "dloam/io/kitti.hpp"

namespace dloam::ros1 {

/// The PointCloud2 topics of a bag, sorted. Throws dloam::InputError when the file is not a
/// readable rosbag.
std::vector<std::string> pointcloud2_topics(const std::string& bag_path);

/// Opens `topic` of the bag (empty: the bag's only PointCloud2 topic) as a sequence: one scan per
/// message in recording order, `times` = header stamps in seconds (the record time when a stamp
/// is zero); no poses, labels or calibration. Scans are read lazily through `Sequence::source`
/// and each is named "<bag>: topic <topic>, message <i>" in errors. Throws dloam::InputError for
/// an unreadable bag, no such topic, a topic of another type, several PointCloud2 topics and no
/// topic given, no PointCloud2 topic, a topic without messages.
io::Sequence open_bag_sequence(const std::string& bag_path, const std::string& topic);

/// Makes io::open_sequence() (hence `dloam run`, `dloam check`) open .bag files.
void register_bag_format();

}  // namespace dloam::ros1
