// `dloam check` and `dloam run` on rosbags: every bad message reported, and a bag of the first
// 5 real scans giving the same poses as the sequence folder.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>

#include "cli_util.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/ros/pointcloud2.hpp"
#include "rosbag_test_util.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;

TEST(Rosbag, CheckReportsEveryBadMessageOfABag) {
  TempDir dir;
  const KnownScan scan = known_scan(50, 4);
  auto truncated = make_cloud(scan, kPlain, 14, 1, kStamp0 + 0.1);
  truncated.data.resize(20);
  const std::string bag = dir.file("check.bag");
  write_bag(bag, {{"/points", make_cloud(scan, kVelodyne, 32, 1, kStamp0)}, {"/points", truncated}});
  const CliRun bad = run_dloam("check " + bag);
  EXPECT_EQ(bad.status, 1) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("2 PointCloud2 messages, 1 readable"));
  EXPECT_THAT(bad.output, HasSubstr("problem: " + bag + ": topic /points, message 1: truncated"));
  EXPECT_THAT(bad.output, HasSubstr("times         yes (2 times"));
  const CliRun missing = run_dloam("check " + bag + " --topic /nope");
  EXPECT_EQ(missing.status, 1);
  EXPECT_THAT(missing.output, HasSubstr("no topic '/nope'"));
}

/// The first 5 scans of the real drive as a bag (float32 x y z intensity, stamps from times.txt)
/// give the same poses as the sequence folder: same clouds, deterministic pipeline.
TEST(Rosbag, RunOnABagOfRealScansGivesTheFolderPoses) {
  const std::string data = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(data + "/velodyne/000000.bin")) GTEST_SKIP() << "no " << data;
  TempDir dir;
  const io::Sequence folder = io::open_sequence(data);
  const std::string bag = dir.file("kitti5.bag");
  {
    rosbag::Bag b(bag, rosbag::bagmode::Write);
    b.setCompression(rosbag::compression::LZ4);
    for (std::size_t i = 0; i < 5; ++i) {
      sensor_msgs::PointCloud2 msg = ros1::to_pointcloud2(folder.read_scan(i));
      msg.header.stamp.fromSec(kStamp0 + folder.times[i]);
      msg.header.frame_id = "velodyne";
      b.write("/kitti/velo/pointcloud", msg.header.stamp, msg);
    }
  }
  const std::string config = std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";
  const CliRun from_bag = run_dloam("run " + bag + " --out " + dir.file("bag") + " --config " + config);
  ASSERT_EQ(from_bag.status, 0) << from_bag.output;
  EXPECT_THAT(from_bag.output, HasSubstr("topic /kitti/velo/pointcloud"));
  const CliRun from_folder =
      run_dloam("run " + data + " --count 5 --out " + dir.file("folder") + " --config " + config);
  ASSERT_EQ(from_folder.status, 0) << from_folder.output;

  const auto bag_poses = io::read_kitti_poses(dir.file("bag/poses.txt"));  // no calib: LiDAR frame
  const auto folder_poses =
      io::camera_to_lidar(io::read_kitti_poses(dir.file("folder/poses.txt")), folder.calib->Tr);
  ASSERT_EQ(bag_poses.size(), 5u);
  ASSERT_EQ(folder_poses.size(), 5u);
  EXPECT_GT(folder_poses.back().translation().norm(), 1.0);  // the car moved: a real comparison
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_LT((bag_poses[i].matrix() - folder_poses[i].matrix()).cwiseAbs().maxCoeff(), 1e-6) << "scan " << i;
  const auto tum = io::read_tum_poses(dir.file("bag/poses_tum.txt"));
  ASSERT_EQ(tum.size(), 5u);
  EXPECT_NEAR(tum[4].t, kStamp0 + folder.times[4], 1e-6);
}

}  // namespace
}  // namespace dloam
