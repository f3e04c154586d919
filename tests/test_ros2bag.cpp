// ROS 2 bags of raw packets: the nebula rosbag2 folders as the sensors README states them
// (messages, packets per message, packet sizes), message order and times, damaged files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <numeric>

#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;
namespace fs = std::filesystem;

const std::string kSensors = DLOAM_SENSORS_DIR;

/// The bag folder inside a nebula model folder (the only subfolder).
std::string bag_folder(const std::string& model_dir) {
  for (const auto& e : fs::directory_iterator(kSensors + "/" + model_dir))
    if (e.is_directory()) return e.path().string();
  return {};
}

struct Expected {
  const char* dir;
  const char* topic;
  const char* type;
  std::vector<std::size_t> packets_per_message;  ///< empty: only the total is stated
  std::size_t total_packets;
  std::size_t packet_size;
  std::size_t messages;
};

struct Decoded {
  std::vector<std::size_t> per_message;
  std::size_t total = 0;
  std::map<std::size_t, std::size_t> sizes;
};

Decoded decode_all(const io::Bag& bag, const std::string& topic, const std::string& type) {
  Decoded out;
  for (std::size_t k = 0; k < bag.message_count(topic); ++k) {
    const auto data = bag.read(topic, k);
    const io::PacketMessage m = io::decode_packet_message(
        type, data.data(), data.size(), 1e-9 * bag.message_time_ns(topic, k), bag.where(topic, k));
    out.per_message.push_back(m.packets.size());
    out.total += m.packets.size();
    for (const auto& p : m.packets) {
      ++out.sizes[p.size];
      EXPECT_LE(p.offset + p.size, data.size());
    }
  }
  return out;
}

TEST(Ros2Bag, NebulaBagsHoldThePacketsTheReadmeLists) {
  if (!fs::exists(kSensors + "/README.md")) GTEST_SKIP() << "no " << kSensors;
  const char* velodyne = "velodyne_msgs/msg/VelodyneScan";
  const char* pandar = "pandar_msgs/msg/PandarScan";
  const std::vector<Expected> cases = {
      {"velodyne/nebula/vlp16", "/velodyne_packets", velodyne, {151, 151, 151, 150}, 603, 1206, 4},
      {"velodyne/nebula/vlp32",
       "/sensing/lidar/front/velodyne_packets",
       velodyne,
       {76, 76, 76, 75, 76},
       379,
       1206,
       5},
      {"velodyne/nebula/vls128", "/velodyne_packets", velodyne, {383, 603, 603, 604}, 2193, 1206, 4},
      {"hesai/nebula/40p", "/pandar_packets", pandar, {}, 1439, 1262, 4},
      {"hesai/nebula/64", "/pandar_packets", pandar, {}, 2400, 1198, 4},
      {"hesai/nebula/qt64", "/pandar_packets", pandar, {}, 1200, 1072, 4},
      {"hesai/nebula/qt128", "/pandar_packets", pandar, {}, 1800, 1127, 2},
      {"hesai/nebula/xt16", "/pandar_packets", pandar, {126, 500, 500, 500}, 1626, 568, 4},
      {"hesai/nebula/xt32", "/pandar_packets", pandar, {}, 2000, 1080, 4},
      {"hesai/nebula/xt32m", "/pandar_packets", pandar, {667, 253, 623, 272}, 1815, 820, 4},
  };
  for (const auto& c : cases) {
    const io::Bag bag(bag_folder(c.dir));
    ASSERT_EQ(bag.topics().size(), 1u) << c.dir;
    EXPECT_EQ(bag.topics()[0].name, c.topic) << c.dir;
    EXPECT_EQ(bag.topics()[0].type, c.type) << c.dir;
    EXPECT_EQ(bag.topics()[0].messages, c.messages) << c.dir;
    ASSERT_EQ(bag.message_count(c.topic), c.messages) << c.dir;
    const Decoded d = decode_all(bag, c.topic, c.type);
    if (!c.packets_per_message.empty()) {
      EXPECT_EQ(d.per_message, c.packets_per_message) << c.dir;
    }
    EXPECT_EQ(d.total, c.total_packets) << c.dir;
    EXPECT_EQ(d.sizes, (std::map<std::size_t, std::size_t>{{c.packet_size, c.total_packets}})) << c.dir;
    for (std::size_t k = 1; k < c.messages; ++k)
      EXPECT_GE(bag.message_time_ns(c.topic, k), bag.message_time_ns(c.topic, k - 1)) << c.dir;
  }
}

TEST(Ros2Bag, PacketSlicesPointAtThePacketsWithTheirStamps) {
  const std::string dir = kSensors + "/velodyne/nebula/vlp16";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir;
  const io::Bag bag(bag_folder("velodyne/nebula/vlp16"));
  const std::string topic = "/velodyne_packets";
  // The reference cloud is named after the last message's timestamp.
  EXPECT_EQ(bag.message_time_ns(topic, 3), 1673400472138016708);
  const auto data = bag.read(topic, 0);
  const auto m = io::decode_packet_message("velodyne_msgs/msg/VelodyneScan", data.data(), data.size(), 0.0,
                                           bag.where(topic, 0));
  ASSERT_EQ(m.packets.size(), 151u);
  double last = 0.0;
  for (const auto& p : m.packets) {
    EXPECT_EQ(data[p.offset], 0xFF);  // block flag FF EE
    EXPECT_EQ(data[p.offset + 1], 0xEE);
    EXPECT_EQ(data[p.offset + 1204], 0x39);  // dual return
    EXPECT_EQ(data[p.offset + 1205], 0x22);  // VLP-16
    EXPECT_GE(p.stamp, last);
    last = p.stamp;
  }
  EXPECT_GT(m.stamp, 1673400471.0);
  EXPECT_LT(m.stamp, 1673400472.2);
  // Pandar64 payloads start with their EE FF header; only `size` of the 1500 bytes are kept.
  const io::Bag hesai(bag_folder("hesai/nebula/64"));
  const auto h = hesai.read("/pandar_packets", 1);
  const auto hm = io::decode_packet_message("pandar_msgs/msg/PandarScan", h.data(), h.size(), 0.0, "h");
  ASSERT_FALSE(hm.packets.empty());
  EXPECT_EQ(h[hm.packets[0].offset], 0xEE);
  EXPECT_EQ(h[hm.packets[0].offset + 1], 0xFF);
  EXPECT_EQ(h[hm.packets[0].offset + 2], 64);  // laser_num
}

TEST(Ros2Bag, ASingleDb3FileOpensWithoutItsFolder) {
  const std::string folder = kSensors + "/hesai/nebula/qt128";
  if (!fs::exists(folder)) GTEST_SKIP() << "no " << folder;
  const std::string dir = bag_folder("hesai/nebula/qt128");
  std::string db3;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".db3") db3 = e.path().string();
  const io::Bag bag(db3);
  EXPECT_EQ(bag.message_count("/pandar_packets"), 2u);
  EXPECT_THAT(bag.describe(), HasSubstr("rosbag2 SQLite"));
  // The same file from memory, as a fuzzer reads it.
  std::ifstream in(db3, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  const auto mem = io::bag_detail::open_sqlite_memory(bytes, "mem.db3");
  const auto refs = mem->index("/pandar_packets");
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(mem->read(refs[1], "m"), bag.read("/pandar_packets", 1));
  EXPECT_THAT(input_error_of([&] {
                io::bag_detail::open_sqlite_memory({1, 2, 3}, "junk.db3");
              }),
              HasSubstr("junk.db3: "));
}

/// A bag copied into a temp folder (its db3 split into two files) reads as one time-ordered view.
TEST(Ros2Bag, SeveralStorageFilesMergeInTimeOrder) {
  const std::string src_dir = kSensors + "/velodyne/nebula/vlp16";
  if (!fs::exists(src_dir)) GTEST_SKIP() << "no " << src_dir;
  TempDir dir;
  const std::string src = bag_folder("velodyne/nebula/vlp16");
  std::string db3;
  for (const auto& e : fs::directory_iterator(src))
    if (e.path().extension() == ".db3") db3 = e.path().string();
  const std::string a = dir.file("bag/bag_0.db3"), b = dir.file("bag/bag_1.db3");
  fs::create_directories(dir.file("bag"));
  fs::copy_file(db3, a);
  fs::copy_file(db3, b);
  for (const auto& [file, sql] :
       {std::pair<std::string, const char*>{a, "DELETE FROM messages WHERE id % 2 = 0"},
        {b, "DELETE FROM messages WHERE id % 2 = 1"}}) {
    fs::permissions(file, fs::perms::owner_write, fs::perm_options::add);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  write_text(dir.file("bag/metadata.yaml"),
             "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
             "  relative_file_paths:\n    - bag_1.db3\n    - bag_0.db3\n");
  const io::Bag merged(dir.file("bag"));
  const io::Bag original(src);
  ASSERT_EQ(merged.message_count("/velodyne_packets"), 4u);
  EXPECT_EQ(merged.topics()[0].messages, 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(merged.message_time_ns("/velodyne_packets", k),
              original.message_time_ns("/velodyne_packets", k));
    EXPECT_EQ(merged.read("/velodyne_packets", k), original.read("/velodyne_packets", k));
  }
  EXPECT_THAT(merged.describe(), HasSubstr("2 files"));
}

TEST(Ros2Bag, DamagedBagsAreInputErrorsNamingTheFile) {
  TempDir dir;
  const std::string junk = dir.file("junk.db3");
  write_text(junk, std::string(4096, 'x'));
  EXPECT_THAT(input_error_of([&] { io::Bag b(junk); }),
              HasSubstr(junk + ": not a readable rosbag2 SQLite file"));
  // An SQLite file that is not a bag.
  const std::string other = dir.file("other.db3");
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(other.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE t(x INTEGER)", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  EXPECT_THAT(input_error_of([&] { io::Bag b(other); }),
              HasSubstr(other + ": is an SQLite file but not a rosbag2"));
  EXPECT_THAT(input_error_of([&] { io::Bag b(dir.path.string()); }), HasSubstr("without metadata.yaml"));
  write_text(dir.file("m/metadata.yaml"),
             "rosbag2_bagfile_information:\n  relative_file_paths: [gone_0.db3]\n");
  EXPECT_THAT(input_error_of([&] { io::Bag b(dir.file("m")); }),
              HasSubstr("lists gone_0.db3, which is not in the folder"));
  write_text(dir.file("y/metadata.yaml"), "rosbag2_bagfile_information: [unclosed\n");
  EXPECT_THAT(input_error_of([&] { io::Bag b(dir.file("y")); }),
              HasSubstr("not a readable rosbag2 metadata file"));

  // A real bag whose file is cut in the middle: the damage is reported, never a crash.
  const std::string src_dir = kSensors + "/hesai/nebula/xt32";
  if (!fs::exists(src_dir)) GTEST_SKIP() << "no " << src_dir;
  std::string db3;
  for (const auto& e : fs::directory_iterator(bag_folder("hesai/nebula/xt32")))
    if (e.path().extension() == ".db3") db3 = e.path().string();
  std::ifstream in(db3, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = dir.file("cut.db3");
  write_text(cut, bytes.substr(0, bytes.size() / 2));
  const std::string error = input_error_of([&] {
    io::Bag b(cut);
    for (std::size_t k = 0; k < b.message_count("/pandar_packets"); ++k) (void)b.read("/pandar_packets", k);
  });
  EXPECT_THAT(error, HasSubstr(cut));
}

}  // namespace
}  // namespace dloam
