// Writes a rosbag2 bag folder: metadata.yaml (version 5) and one SQLite storage file
// (<name>_0.db3) with the tables ROS 2 Humble writes. The folder is built as `<dir>.part` and
// renamed to `dir` by close(), so an interrupted writer leaves no half-written bag.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace dloam::io {

class Rosbag2Writer {
 public:
  /// `dir` must not exist yet.
  explicit Rosbag2Writer(const std::string& dir);
  ~Rosbag2Writer();  ///< without close(): the unfinished folder is deleted
  Rosbag2Writer(const Rosbag2Writer&) = delete;
  Rosbag2Writer& operator=(const Rosbag2Writer&) = delete;

  void add_topic(const std::string& name, const std::string& type, const std::string& serialization = "cdr");
  void write(const std::string& topic, std::int64_t time_ns, const std::uint8_t* data, std::size_t size);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dloam::io
