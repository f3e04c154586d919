// Structural check of a ROS 1 bag (format 2.0) before the rosbag library opens it. The library
// trusts the lengths and offsets stored in the file: a corrupt record header makes it allocate
// what the header claims (2 GB from a 4-byte field) or parse from the middle of a record. This
// walks every record and checks what the library will rely on; errors are dloam::InputError
// naming the bag and the byte offset. ROS-free. Internal to dloam_ros.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace dloam::ros1 {

/// Throws InputError unless `path` is a version 2.0 bag whose records are all well formed:
/// record headers of at most 1 MiB made of `name=value` fields, record data within the file,
/// numeric fields of their size, a bag header whose index position is a record boundary, chunk
/// compression none / bz2 / lz4 with a plausible uncompressed size (the records inside an
/// uncompressed chunk, and their index offsets, are checked too), index and chunk-info counts
/// that fit their data, chunk-info positions at chunk records.
void check_bag_structure(const std::string& path);

/// Throws InputError naming `where` unless `data` (a serialised sensor_msgs/PointCloud2) holds
/// every length it announces (strings, the fields array, the point data): the deserialiser
/// resizes its vectors to those lengths before it checks them.
void check_pointcloud2_lengths(const std::uint8_t* data, std::size_t size, const std::string& where);

}  // namespace dloam::ros1
