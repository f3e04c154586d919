// Reads only the std_msgs/Header stamp at the start of a serialised message (every stamped
// message begins with uint32 seq, time stamp, string frame_id), so opening a bag lists the scan
// times without deserialising whole clouds. Internal to dloam_ros.
#pragma once

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <ros/time.h>

namespace dloam::ros1 {
struct HeaderStamp {
  ::ros::Time stamp;
};
}  // namespace dloam::ros1

namespace ros {
namespace message_traits {
// "*": rosbag instantiates it from a message of any type.
template <>
struct MD5Sum<dloam::ros1::HeaderStamp> {
  static const char* value() { return "*"; }
  static const char* value(const dloam::ros1::HeaderStamp&) { return "*"; }
};
template <>
struct DataType<dloam::ros1::HeaderStamp> {
  static const char* value() { return "*"; }
  static const char* value(const dloam::ros1::HeaderStamp&) { return "*"; }
};
template <>
struct Definition<dloam::ros1::HeaderStamp> {
  static const char* value() { return ""; }
  static const char* value(const dloam::ros1::HeaderStamp&) { return ""; }
};
}  // namespace message_traits

namespace serialization {
template <>
struct Serializer<dloam::ros1::HeaderStamp> {
  template <typename Stream>
  static void read(Stream& stream, dloam::ros1::HeaderStamp& h) {
    std::uint32_t seq = 0;
    stream.next(seq);
    stream.next(h.stamp);
  }
};
}  // namespace serialization
}  // namespace ros
