// rosbag input on unusual recordings: repeated and reordered header stamps, NaN per-point times
// and out-of-range intensities of real points, record and message lengths that lie.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <limits>

#include "dloam/ros/bag_check.hpp"
#include "dloam/ros/bag_sequence.hpp"
#include "dloam/ros/pointcloud2.hpp"
#include "rosbag_test_util.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::test;
using ::testing::HasSubstr;

TEST(RosbagHardening, RepeatedOrReorderedStampsAreErrorsNamingTheMessage) {
  TempDir dir;
  const KnownScan scan = known_scan(30, 4);
  for (const auto& [name, second] : {std::pair<const char*, double>{"same.bag", 0.0}, {"back.bag", -0.05}}) {
    // Record times increase (rosbag plays messages in record-time order); the header stamps repeat
    // or go back.
    rosbag::Bag bag(dir.file(name), rosbag::bagmode::Write);
    const double stamps[3] = {kStamp0, kStamp0 + 0.1, kStamp0 + 0.1 + second};
    for (int k = 0; k < 3; ++k)
      bag.write("/points", ros::Time(kStamp0 + 0.1 * k), make_cloud(scan, kPlain, 14, 1, stamps[k]));
    bag.close();
    const std::string path = dir.file(name);  // C++17 lambdas cannot capture structured bindings
    const std::string msg = input_error_of([&] { (void)ros1::open_bag_sequence(path, ""); });
    EXPECT_THAT(msg, HasSubstr(name));
    EXPECT_THAT(msg, HasSubstr("message 2"));
    EXPECT_THAT(msg, HasSubstr("scan times must increase"));
  }
}

TEST(RosbagHardening, NanTimesAndOutOfRangeIntensitiesOfRealPointsAreErrors) {
  const KnownScan scan = known_scan(20, 5);
  sensor_msgs::PointCloud2 msg = make_cloud(scan, kVelodyne, 32, 1, kStamp0);
  put(msg.data, 4 * 32 + 24, std::numeric_limits<float>::quiet_NaN());  // time of point 4
  EXPECT_THAT(input_error_of([&] { (void)ros1::from_pointcloud2(msg, "t.bag"); }),
              HasSubstr("point 4 has a NaN"));
  sensor_msgs::PointCloud2 wide = make_cloud(scan, kDouble, 32, 1, kStamp0);
  wide.fields.push_back(wide.fields.back());
  wide.fields.back().name = "intensity";  // float64 intensity = the timestamp field, then 1e300
  put(wide.data, 7 * 32 + 24, 1e300);
  EXPECT_THAT(input_error_of([&] { (void)ros1::from_pointcloud2(wide, "i.bag"); }), HasSubstr("intensity"));
}

namespace {
/// The bytes of a small bag and the offset of its bag header's index position.
std::string bag_bytes(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  const KnownScan scan = known_scan(16, 2);
  for (int k = 0; k < 2; ++k)
    bag.write("/points", ros::Time(kStamp0 + 0.1 * k), make_cloud(scan, kPlain, 14, 1, kStamp0 + 0.1 * k));
  bag.close();
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::uint64_t index_pos(const std::string& bag) {
  const auto at = bag.find("index_pos=");
  std::uint64_t pos = 0;
  std::memcpy(&pos, bag.data() + at + 10, 8);
  return pos;
}
}  // namespace

TEST(RosbagHardening, CorruptRecordLengthsAreErrorsBeforeTheLibraryAllocatesThem) {
  // Found by fuzz/fuzz_rosbag.cpp: a connection record whose header length claims 2.3 GB made
  // rosbag::Bag::open() allocate it (out of memory).
  TempDir dir;
  const std::string good = bag_bytes(dir.file("good.bag"));
  const std::uint64_t pos = index_pos(good);
  ASSERT_LT(pos + 4, good.size());
  std::string huge = good;
  const std::uint32_t claim = 0x8A000000u;
  std::memcpy(huge.data() + pos, &claim, 4);
  write_text(dir.file("huge.bag"), huge);
  const std::string msg = input_error_of([&] { (void)ros1::open_bag_sequence(dir.file("huge.bag"), ""); });
  EXPECT_THAT(msg, HasSubstr("huge.bag: not a readable rosbag"));
  EXPECT_THAT(msg, HasSubstr("byte " + std::to_string(pos)));
  // The index position in the middle of a record; a truncated file; not a bag at all.
  std::string shifted = good;
  const std::uint64_t wrong = pos + 2;
  std::memcpy(shifted.data() + good.find("index_pos=") + 10, &wrong, 8);
  write_text(dir.file("shifted.bag"), shifted);
  EXPECT_THAT(input_error_of([&] { (void)ros1::open_bag_sequence(dir.file("shifted.bag"), ""); }),
              HasSubstr("is not a record"));
  write_text(dir.file("cut.bag"), good.substr(0, good.size() - 7));
  EXPECT_THAT(input_error_of([&] { (void)ros1::open_bag_sequence(dir.file("cut.bag"), ""); }),
              HasSubstr("cut.bag"));
  write_text(dir.file("text.bag"), "#ROSBAG V1.2\n");
  EXPECT_THAT(input_error_of([&] { (void)ros1::open_bag_sequence(dir.file("text.bag"), ""); }),
              HasSubstr("2.0"));
  // The good bag still opens and reads.
  const auto seq = ros1::open_bag_sequence(dir.file("good.bag"), "");
  EXPECT_EQ(seq.read_scan(1).size(), 16u);
}

TEST(RosbagHardening, APointCloud2WhoseLengthsRunPastTheMessageIsAnError) {
  sensor_msgs::PointCloud2 msg = make_cloud(known_scan(8, 1), kPlain, 14, 1, kStamp0);
  std::vector<std::uint8_t> raw(ros::serialization::serializationLength(msg));
  ros::serialization::OStream out(raw.data(), static_cast<std::uint32_t>(raw.size()));
  ros::serialization::serialize(out, msg);
  EXPECT_NO_THROW(ros1::check_pointcloud2_lengths(raw.data(), raw.size(), "m"));
  // The data length (just before the 8 x 14 data bytes and is_dense) claims 4 GB.
  const std::uint32_t claim = 0xFFFFFFF0u;
  std::memcpy(raw.data() + raw.size() - 1 - 8 * 14 - 4, &claim, 4);
  EXPECT_THAT(
      input_error_of([&] { ros1::check_pointcloud2_lengths(raw.data(), raw.size(), "b.bag: message 3"); }),
      HasSubstr("b.bag: message 3: cannot be read"));
}
