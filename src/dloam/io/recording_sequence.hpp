// Recordings as sequences: pcap captures and ROS 2 bags (PointCloud2 topics, or the drivers'
// packet topics decoded by the vendor scanners). Used by open_sequence() (kitti.hpp).
#pragma once

#include <string>
#include <vector>

#include "dloam/io/bag.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::io {

/// A capture: the data packets of one sensor (the port given, else the port of the first
/// datagram a vendor decoder claims) decoded into scans.
Sequence open_pcap_sequence(const std::string& path, const InputOptions& input);

/// A ROS 2 bag: a PointCloud2 topic read message by message, or a packet topic decoded into scans.
Sequence open_bag2_sequence(const std::string& path, const InputOptions& input);

/// The topic of a bag to read: `topic` when given (of PointCloud2 or a packet type), else the
/// only PointCloud2 topic, else the only packet topic (Ouster: the one that is not IMU). Throws
/// InputError listing the candidates when that is ambiguous, or none is there.
std::string choose_bag_topic(const Bag& bag, const std::string& topic);

/// The Ouster metadata JSON beside a recording: `<stem>.json`, else the JSON named like the
/// stem shortened at its last '_' or '-' (`drive_part2.pcap` -> `drive.json`); empty if none.
std::string ouster_metadata_beside(const std::string& recording);

}  // namespace dloam::io
