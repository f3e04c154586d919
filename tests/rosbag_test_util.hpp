// Helpers of the rosbag tests: a known scan, hand-made sensor_msgs/PointCloud2 messages in the
// field layouts of the Velodyne and Ouster drivers (and plain / float64 ones), bag writing.
#pragma once

#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace dloam::test {

using sensor_msgs::PointField;

/// One field of a hand-made PointCloud2 layout.
struct FieldSpec {
  const char* name;
  std::uint32_t offset;
  std::uint8_t type;
};

/// The known scan: float-representable coordinates and intensities, point i fired at i / n of the
/// sweep.
struct KnownScan {
  std::vector<std::array<float, 3>> xyz;
  std::vector<float> intensity;
};

inline KnownScan known_scan(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-40.0f, 40.0f), refl(0.0f, 255.0f);
  KnownScan s;
  for (std::size_t i = 0; i < n; ++i) {
    s.xyz.push_back({coord(rng), coord(rng), coord(rng) / 10.0f});
    s.intensity.push_back(std::round(refl(rng)));
  }
  return s;
}

template <class T>
void put(std::vector<std::uint8_t>& data, std::size_t at, T value) {
  std::memcpy(data.data() + at, &value, sizeof(T));
}

/// A message with the given layout (height x width, row-major), filled from `scan`; a time field
/// gets point i's time (i / n of a 0.1 s sweep) in its driver's convention, by its name.
inline sensor_msgs::PointCloud2 make_cloud(const KnownScan& scan, const std::vector<FieldSpec>& fields,
                                           std::uint32_t point_step, std::uint32_t height, double stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp.fromSec(stamp);
  msg.header.frame_id = "lidar";
  msg.height = height;
  msg.width = static_cast<std::uint32_t>(scan.xyz.size()) / height;
  msg.point_step = point_step;
  msg.row_step = msg.width * point_step;
  msg.is_dense = true;
  for (const auto& f : fields) {
    sensor_msgs::PointField pf;
    pf.name = f.name;
    pf.offset = f.offset;
    pf.datatype = f.type;
    pf.count = 1;
    msg.fields.push_back(pf);
  }
  const std::size_t n = scan.xyz.size();
  msg.data.assign(n * point_step, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t base = i * point_step;
    const double fraction = static_cast<double>(i) / static_cast<double>(n);
    for (const auto& f : fields) {
      const std::string name = f.name;
      const std::size_t at = base + f.offset;
      if (name == "x" || name == "y" || name == "z") {
        const float v = scan.xyz[i][name[0] - 'x'];
        if (f.type == PointField::FLOAT64)
          put(msg.data, at, static_cast<double>(v));
        else if (f.type == PointField::FLOAT32)
          put(msg.data, at, v);
        else
          put(msg.data, at, static_cast<std::uint16_t>(std::abs(v)));
      } else if (name == "intensity") {
        if (f.type == PointField::UINT16)
          put(msg.data, at, static_cast<std::uint16_t>(scan.intensity[i]));
        else
          put(msg.data, at, scan.intensity[i]);
      } else if (name == "time") {  // Velodyne: float32 seconds from the first firing, 10 Hz
        put(msg.data, at, static_cast<float>(0.1 * fraction));
      } else if (name == "t") {  // Ouster: uint32 nanoseconds
        put(msg.data, at, static_cast<std::uint32_t>(std::llround(1e8 * fraction)));
      } else if (name == "timestamp") {  // Hesai: float64 absolute seconds
        put(msg.data, at, stamp + 0.1 * fraction);
      } else if (name == "ring") {
        put(msg.data, at, static_cast<std::uint16_t>(i % 64));
      }
    }
  }
  return msg;
}

const std::vector<FieldSpec> kVelodyne = {
    {"x", 0, PointField::FLOAT32},    {"y", 4, PointField::FLOAT32},
    {"z", 8, PointField::FLOAT32},    {"intensity", 16, PointField::FLOAT32},
    {"ring", 20, PointField::UINT16}, {"time", 24, PointField::FLOAT32}};
const std::vector<FieldSpec> kOuster = {
    {"x", 0, PointField::FLOAT32},    {"y", 4, PointField::FLOAT32},
    {"z", 8, PointField::FLOAT32},    {"intensity", 16, PointField::FLOAT32},
    {"t", 20, PointField::UINT32},    {"reflectivity", 24, PointField::UINT16},
    {"ring", 26, PointField::UINT16}, {"range", 32, PointField::UINT32}};
const std::vector<FieldSpec> kPlain = {{"x", 0, PointField::FLOAT32},
                                       {"y", 4, PointField::FLOAT32},
                                       {"z", 8, PointField::FLOAT32},
                                       {"intensity", 12, PointField::UINT16}};
const std::vector<FieldSpec> kDouble = {{"x", 0, PointField::FLOAT64},
                                        {"y", 8, PointField::FLOAT64},
                                        {"z", 16, PointField::FLOAT64},
                                        {"timestamp", 24, PointField::FLOAT64}};

constexpr double kStamp0 = 1317000000.25;

/// Writes each (topic, message) in order, with the header stamp as record time.
inline void write_bag(const std::string& path,
                      const std::vector<std::pair<std::string, sensor_msgs::PointCloud2>>& msgs) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (const auto& [topic, msg] : msgs) bag.write(topic, msg.header.stamp, msg);
  bag.close();
}

}  // namespace dloam::test
