// rosbag input on unusual recordings: repeated and reordered header stamps, NaN per-point times
// and out-of-range intensities of real points.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

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
    const std::string msg = input_error_of([&] { (void)ros1::open_bag_sequence(dir.file(name), ""); });
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
