// rosbag input (see bag_sequence.hpp): indexes the messages of one topic, reads their header
// stamps without deserialising the clouds, converts a cloud when its scan is read.
#include "dloam/ros/bag_sequence.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <atomic>
#include <boost/make_shared.hpp>
#include <memory>
#include <mutex>
#include <set>

#include "dloam/ros/bag_check.hpp"
#include "dloam/ros/bag_stamp.hpp"
#include "dloam/ros/pointcloud2.hpp"

namespace dloam::ros1 {

namespace {
constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

std::unique_ptr<rosbag::Bag> open_bag(const std::string& path) {
  // The library allocates what a record's length fields claim: check them first.
  check_bag_structure(path);
  auto bag = std::make_unique<rosbag::Bag>();
  try {
    bag->open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    fail(path, std::string("not a readable rosbag (") + e.what() + ")");
  }
  return bag;
}

std::string join(const std::set<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

/// Topic -> datatype of every connection of the bag.
std::map<std::string, std::string> bag_topics(const rosbag::Bag& bag) {
  std::map<std::string, std::string> topics;
  rosbag::View view(bag);
  for (const rosbag::ConnectionInfo* c : view.getConnections()) topics[c->topic] = c->datatype;
  return topics;
}

std::string choose_topic(const std::string& path, const std::map<std::string, std::string>& topics,
                         const std::string& topic) {
  std::set<std::string> clouds, all;
  for (const auto& [name, type] : topics) {
    all.insert(name + " (" + type + ")");
    if (type == kPointCloud2) clouds.insert(name);
  }
  if (!topic.empty()) {
    const auto it = topics.find(topic);
    if (it == topics.end()) fail(path, "no topic '" + topic + "' (PointCloud2 topics: " + join(clouds) + ")");
    if (it->second != kPointCloud2)
      fail(path, "topic '" + topic + "' has type " + it->second + ", expected " + kPointCloud2);
    return topic;
  }
  if (clouds.empty()) fail(path, std::string("no ") + kPointCloud2 + " topic (topics: " + join(all) + ")");
  if (clouds.size() > 1)
    fail(path, "has several PointCloud2 topics (" + join(clouds) + "): choose one with --topic");
  return *clouds.begin();
}

/// Reads the messages of one topic on demand. rosbag::Bag reads through shared buffers, so reads
/// are serialised.
class BagSource : public io::ScanSource {
 public:
  BagSource(std::string path, std::string topic, std::unique_ptr<rosbag::Bag> bag)
      : path_(std::move(path)), topic_(std::move(topic)), bag_(std::move(bag)) {
    rosbag::View view(*bag_, rosbag::TopicQuery(topic_));
    for (const rosbag::MessageInstance& m : view) messages_.push_back(m);
  }

  [[nodiscard]] std::size_t size() const { return messages_.size(); }
  [[nodiscard]] std::string name(std::size_t i) const {
    return path_ + ": topic " + topic_ + ", message " + std::to_string(i);
  }

  /// Header stamp of message i in seconds; the record time when the stamp is zero.
  [[nodiscard]] double stamp(std::size_t i) const {
    const auto header = instantiate<HeaderStamp>(i);
    return header->stamp.isZero() ? messages_[i].getTime().toSec() : header->stamp.toSec();
  }

  [[nodiscard]] PointCloud read(std::size_t i) const override {
    const auto msg = instantiate_cloud(i);
    ConvertedCloud converted = from_pointcloud2(*msg, name(i));
    dropped_ += converted.dropped;
    return std::move(converted.cloud);
  }

  [[nodiscard]] std::string describe() const override {
    return "rosbag " + path_ + ", topic " + topic_ + " (" + kPointCloud2 + "), " + std::to_string(size()) +
           " messages; NaN/Inf points dropped from is_dense=false clouds in the scans read: " +
           std::to_string(dropped_.load());
  }

 private:
  template <class T>
  boost::shared_ptr<T> instantiate(std::size_t i) const {
    std::lock_guard<std::mutex> lock(mutex_);
    boost::shared_ptr<T> msg;
    try {
      msg = messages_.at(i).instantiate<T>();
    } catch (const std::exception& e) {  // rosbag::BagException, ros::serialization::StreamOverrunException
      fail(name(i), std::string("cannot be read (") + e.what() + ")");
    }
    if (!msg) fail(name(i), "has another definition of " + std::string(kPointCloud2) + " (MD5 sum differs)");
    return msg;
  }

  /// Message i as a PointCloud2, its lengths checked before deserialising (which resizes
  /// vectors to whatever the bytes say).
  boost::shared_ptr<sensor_msgs::PointCloud2> instantiate_cloud(std::size_t i) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const rosbag::MessageInstance& m = messages_.at(i);
    if (!m.isType<sensor_msgs::PointCloud2>())
      fail(name(i), "has another definition of " + std::string(kPointCloud2) + " (MD5 sum differs)");
    std::vector<std::uint8_t> raw;
    try {
      raw.resize(m.size());
      ros::serialization::OStream out(raw.data(), static_cast<std::uint32_t>(raw.size()));
      m.write(out);
    } catch (const std::exception& e) {  // rosbag::BagException, ros::serialization::StreamOverrunException
      fail(name(i), std::string("cannot be read (") + e.what() + ")");
    }
    check_pointcloud2_lengths(raw.data(), raw.size(), name(i));
    auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
    try {
      ros::serialization::IStream in(raw.data(), static_cast<std::uint32_t>(raw.size()));
      ros::serialization::deserialize(in, *msg);
    } catch (const std::exception& e) {
      fail(name(i), std::string("cannot be read (") + e.what() + ")");
    }
    return msg;
  }

  std::string path_, topic_;
  std::unique_ptr<rosbag::Bag> bag_;
  std::vector<rosbag::MessageInstance> messages_;
  mutable std::mutex mutex_;
  mutable std::atomic<std::size_t> dropped_{0};
};
}  // namespace

std::vector<std::string> pointcloud2_topics(const std::string& bag_path) {
  const auto bag = open_bag(bag_path);
  std::vector<std::string> out;
  for (const auto& [name, type] : bag_topics(*bag))
    if (type == kPointCloud2) out.push_back(name);
  return out;
}

io::Sequence open_bag_sequence(const std::string& bag_path, const std::string& topic) {
  auto bag = open_bag(bag_path);
  const std::string chosen = choose_topic(bag_path, bag_topics(*bag), topic);
  auto source = std::make_shared<BagSource>(bag_path, chosen, std::move(bag));
  if (source->size() == 0) fail(bag_path, "topic " + chosen + " has no messages");
  io::Sequence seq;
  seq.dir = bag_path;
  for (std::size_t i = 0; i < source->size(); ++i) {
    seq.scan_files.push_back(source->name(i));
    const double stamp = source->stamp(i);
    // Scan times must increase, as in times.txt: a repeated or earlier stamp is a duplicated or
    // reordered message, and the TUM output would repeat or reorder its time.
    if (i > 0 && !(stamp > seq.times.back()))
      fail(source->name(i), "stamp " + std::to_string(stamp) + " s is " +
                                (stamp == seq.times.back() ? "the same as" : "earlier than") + " message " +
                                std::to_string(i - 1) + "'s (" + std::to_string(seq.times.back()) +
                                " s): scan times must increase");
    seq.times.push_back(stamp);
  }
  seq.source = std::move(source);
  return seq;
}

void register_bag_format() { io::register_sequence_format(".bag", open_bag_sequence); }

}  // namespace dloam::ros1
