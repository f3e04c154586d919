// ROS 2 bags: a rosbag2 folder (metadata.yaml + one or more .db3 or .mcap files), a single
// rosbag2 SQLite file (.db3) or a single MCAP file (.mcap). Topics with their types; the
// messages of a topic in log-time order, read one at a time by index (an index of the topic is
// built on first use; message data is read only when asked for). zstd-compressed rosbag2 bags
// (compression_mode MESSAGE or FILE) are read too. Errors are dloam::InputError naming the file,
// the topic and the message index.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dloam::io {

struct BagTopic {
  std::string name, type;
  std::string encoding;  ///< serialization: "cdr" (rosbag2 may leave it empty)
  std::size_t messages = 0;
};

namespace bag_detail {
/// A message of one file: its log time and where the file keeps it.
struct MessageRef {
  std::int64_t time_ns = 0;
  std::uint64_t locator = 0;  ///< SQLite row id / MCAP record offset
};
/// One storage file (SQLite or MCAP) of a bag.
class BagFile {
 public:
  virtual ~BagFile() = default;
  [[nodiscard]] virtual const std::string& path() const = 0;
  [[nodiscard]] virtual std::vector<BagTopic> topics() = 0;
  /// The messages of a topic in log-time order (ties: file order); empty when the file lacks it.
  virtual std::vector<MessageRef> index(const std::string& topic) = 0;
  /// The serialized message; `where` names it in errors.
  virtual std::vector<std::uint8_t> read(const MessageRef& ref, const std::string& where) = 0;
  [[nodiscard]] virtual std::string format() const = 0;  ///< "rosbag2 SQLite", "MCAP (chunked, zstd)"
};
std::unique_ptr<BagFile> open_sqlite_file(const std::string& path);
std::unique_ptr<BagFile> open_mcap_file(const std::string& path);
/// A rosbag2 SQLite image held in memory (fuzzing, tests); `name` is used in errors. The MCAP
/// counterpart is open_mcap_memory() (mcap.hpp).
std::unique_ptr<BagFile> open_sqlite_memory(const std::vector<std::uint8_t>& bytes, const std::string& name);
}  // namespace bag_detail

class Bag {
 public:
  /// Opens a rosbag2 folder (metadata.yaml), a .db3 or a .mcap file. Throws InputError for a
  /// missing / unreadable / damaged file, a bag without topics.
  explicit Bag(const std::string& path);
  ~Bag();
  Bag(const Bag&) = delete;
  Bag& operator=(const Bag&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const { return topics_; }
  [[nodiscard]] const BagTopic* find_topic(const std::string& name) const;
  /// Messages of `topic` (builds its index on first use); throws for an unknown topic.
  [[nodiscard]] std::size_t message_count(const std::string& topic) const;
  [[nodiscard]] std::int64_t message_time_ns(const std::string& topic, std::size_t k) const;
  /// The serialized message k of `topic` (decompressed). Safe to call from several threads.
  [[nodiscard]] std::vector<std::uint8_t> read(const std::string& topic, std::size_t k) const;
  /// "<path>: topic T, message k": how errors name a message.
  [[nodiscard]] std::string where(const std::string& topic, std::size_t k) const;
  /// "rosbag2 SQLite, 1 file" and the like.
  [[nodiscard]] std::string describe() const;

 private:
  struct Entry {
    std::int64_t time_ns;
    std::size_t file;
    std::uint64_t locator;
  };
  const std::vector<Entry>& index(const std::string& topic) const;

  std::string path_;
  std::vector<std::unique_ptr<bag_detail::BagFile>> files_;
  std::vector<BagTopic> topics_;
  bool compressed_messages_ = false;     ///< rosbag2 compression_mode MESSAGE (zstd)
  std::vector<std::string> temp_files_;  ///< rosbag2 compression_mode FILE: the decompressed copies
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::vector<Entry>> indexes_;
};

}  // namespace dloam::io
