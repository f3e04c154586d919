// rosbag input (dloam_ros): PointCloud2 layouts of the Velodyne and Ouster drivers and plain ones,
// written with rosbag_storage and read back through io::open_sequence(); conversion both ways;
// the bad-input errors naming bag, topic and message.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "dloam/io/kitti.hpp"
#include "dloam/ros/bag_sequence.hpp"
#include "dloam/ros/pointcloud2.hpp"
#include "rosbag_test_util.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;

void expect_same_points(const PointCloud& got, const KnownScan& want, bool with_intensity) {
  ASSERT_EQ(got.size(), want.xyz.size());
  ASSERT_EQ(got.has_intensity(), with_intensity);
  for (std::size_t i = 0; i < got.size(); ++i) {
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(got.xyz[i][a], static_cast<double>(want.xyz[i][a])) << "point " << i;
    if (with_intensity) {
      ASSERT_EQ(got.intensity[i], want.intensity[i]) << "point " << i;
    }
  }
}

/// Times must be the sweep fractions i / (n - 1), up to the rounding of the stored times (float64
/// absolute stamps near 1.3e9 s resolve 0.24 us) and the < 1 guard.
void expect_sweep_times(const PointCloud& got) {
  ASSERT_TRUE(got.has_time());
  const double n = static_cast<double>(got.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    ASSERT_NEAR(got.time[i], static_cast<double>(i) / (n - 1.0), 1e-5) << "point " << i;
}

TEST(Rosbag, DriverLayoutsReadBackExactlyThroughTheSequenceReader) {
  TempDir dir;
  const std::string bag = dir.file("drive.bag");
  std::vector<KnownScan> scans;
  std::vector<std::pair<std::string, sensor_msgs::PointCloud2>> msgs;
  for (unsigned k = 0; k < 3; ++k) {
    scans.push_back(known_scan(256, k));
    const double stamp = kStamp0 + 0.1 * k;
    msgs.emplace_back("/velodyne_points", make_cloud(scans[k], kVelodyne, 32, 1, stamp));
    msgs.emplace_back("/os_cloud_node/points", make_cloud(scans[k], kOuster, 48, 4, stamp));  // organised
    msgs.emplace_back("/plain", make_cloud(scans[k], kPlain, 14, 1, stamp));
    msgs.emplace_back("/double", make_cloud(scans[k], kDouble, 32, 2, stamp));
  }
  write_bag(bag, msgs);
  ros1::register_bag_format();
  for (const char* topic : {"/velodyne_points", "/os_cloud_node/points", "/plain", "/double"}) {
    SCOPED_TRACE(topic);
    const io::Sequence seq = io::open_sequence(bag, topic);
    ASSERT_EQ(seq.size(), 3u);
    ASSERT_EQ(seq.times.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      ros::Time expected;
      expected.fromSec(kStamp0 + 0.1 * static_cast<double>(k));
      EXPECT_EQ(seq.times[k], expected.toSec());
      const PointCloud cloud = seq.read_scan(k);
      expect_same_points(cloud, scans[k], std::string(topic) != "/double");
      if (std::string(topic) == "/plain") {
        EXPECT_FALSE(cloud.has_time());
      } else {
        expect_sweep_times(cloud);
      }
    }
  }
  EXPECT_EQ(ros1::pointcloud2_topics(bag),
            (std::vector<std::string>{"/double", "/os_cloud_node/points", "/plain", "/velodyne_points"}));
}

TEST(Rosbag, WriterAndReaderRoundTripWithLabels) {
  PointCloud cloud;
  const KnownScan scan = known_scan(100, 5);
  for (std::size_t i = 0; i < 100; ++i) {
    cloud.xyz.emplace_back(scan.xyz[i][0], scan.xyz[i][1], scan.xyz[i][2]);
    cloud.intensity.push_back(scan.intensity[i]);
    cloud.time.push_back(static_cast<float>(i) / 100.0f);
  }
  std::vector<Label> labels(100, semantic::kStatic);
  labels[7] = semantic::kMovingGeneric;
  const sensor_msgs::PointCloud2 msg = ros1::to_pointcloud2(cloud, labels);
  ASSERT_EQ(msg.fields.size(), 6u);
  EXPECT_EQ(msg.fields.back().name, "label");
  std::uint32_t label7 = 0;
  std::memcpy(&label7, msg.data.data() + 7 * msg.point_step + msg.fields.back().offset, 4);
  EXPECT_EQ(label7, semantic::kMovingGeneric);
  const PointCloud back = ros1::from_pointcloud2(msg, "memory").cloud;
  expect_same_points(back, scan, true);
  ASSERT_TRUE(back.has_time());
  for (std::size_t i = 0; i < 100; ++i) EXPECT_FLOAT_EQ(back.time[i], cloud.time[i]);  // fractions kept
}

TEST(Rosbag, NanPointsAreDroppedOnlyFromCloudsThatAreNotDense) {
  const KnownScan scan = known_scan(40, 9);
  sensor_msgs::PointCloud2 msg = make_cloud(scan, kPlain, 14, 1, kStamp0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  put(msg.data, 3 * 14 + 4, nan);  // y of point 3
  const std::string dense_error = input_error_of([&] { ros1::from_pointcloud2(msg, "b.bag: message 2"); });
  EXPECT_THAT(dense_error, HasSubstr("b.bag: message 2"));
  EXPECT_THAT(dense_error, HasSubstr("point 3 has a NaN"));
  msg.is_dense = false;
  const auto converted = ros1::from_pointcloud2(msg, "b.bag");
  EXPECT_EQ(converted.dropped, 1u);
  ASSERT_EQ(converted.cloud.size(), 39u);
  EXPECT_EQ(converted.cloud.xyz[3].x(), static_cast<double>(scan.xyz[4][0]));  // order kept
  for (std::size_t i = 0; i < 40; ++i) put(msg.data, i * 14, nan);
  EXPECT_THAT(input_error_of([&] { ros1::from_pointcloud2(msg, "b.bag"); }), HasSubstr("no finite point"));
}

TEST(Rosbag, BadMessagesAndTopicsAreInputErrorsNamingFileTopicAndMessage) {
  TempDir dir;
  ros1::register_bag_format();
  const KnownScan scan = known_scan(50, 3);
  const auto good = make_cloud(scan, kPlain, 14, 1, kStamp0);
  auto no_x =
      make_cloud(scan, {{"y", 4, PointField::FLOAT32}, {"z", 8, PointField::FLOAT32}}, 12, 1, kStamp0 + 0.1);
  auto int_x = make_cloud(
      scan, {{"x", 0, PointField::UINT16}, {"y", 4, PointField::FLOAT32}, {"z", 8, PointField::FLOAT32}}, 12,
      1, kStamp0 + 0.2);
  auto truncated = good;
  truncated.header.stamp.fromSec(kStamp0 + 0.3);
  truncated.data.resize(truncated.data.size() - 5);
  const std::string bag = dir.file("bad.bag");
  write_bag(
      bag,
      {{"/points", good}, {"/points", no_x}, {"/points", int_x}, {"/points", truncated}, {"/other", good}});
  {
    rosbag::Bag b(bag, rosbag::bagmode::Append);
    sensor_msgs::Imu imu;
    b.write("/imu", ros::Time(kStamp0), imu);
  }
  const io::Sequence seq = io::open_sequence(bag, "/points");
  ASSERT_EQ(seq.size(), 4u);
  EXPECT_EQ(seq.read_scan(0).size(), 50u);
  const std::string where = bag + ": topic /points, message ";
  EXPECT_THAT(input_error_of([&] { (void)seq.read_scan(1); }), HasSubstr(where + "1: has no 'x' field"));
  EXPECT_THAT(input_error_of([&] { (void)seq.read_scan(2); }),
              HasSubstr(where + "2: field 'x' has datatype uint16, expected float32 or float64"));
  EXPECT_THAT(input_error_of([&] { (void)seq.read_scan(3); }), HasSubstr(where + "3: truncated"));

  EXPECT_THAT(input_error_of([&] { io::open_sequence(bag, "/nope"); }),
              HasSubstr(bag + ": no topic '/nope' (PointCloud2 topics: /other, /points)"));
  EXPECT_THAT(input_error_of([&] { io::open_sequence(bag); }),
              HasSubstr("several PointCloud2 topics (/other, /points): choose one with --topic"));
  EXPECT_THAT(input_error_of([&] { io::open_sequence(bag, "/imu"); }),
              HasSubstr("topic '/imu' has type sensor_msgs/Imu, expected sensor_msgs/PointCloud2"));
  test::write_text(dir.file("text.bag"), "not a bag\n");
  EXPECT_THAT(input_error_of([&] { io::open_sequence(dir.file("text.bag")); }),
              HasSubstr(dir.file("text.bag") + ": not a readable rosbag"));
  const std::string imu_only = dir.file("imu.bag");
  {
    rosbag::Bag b(imu_only, rosbag::bagmode::Write);
    b.write("/imu", ros::Time(kStamp0), sensor_msgs::Imu());
  }
  EXPECT_THAT(input_error_of([&] { io::open_sequence(imu_only); }),
              HasSubstr("no sensor_msgs/PointCloud2 topic (topics: /imu (sensor_msgs/Imu))"));
}
}  // namespace
}  // namespace dloam
