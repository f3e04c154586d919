// Sequence folders: the real KITTI drive, count/name mismatches, PCD folders.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;

namespace {
PointCloud line_cloud(std::size_t n, double offset) {
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) c.xyz.emplace_back(offset + 0.5 * static_cast<double>(i), 1.0, -1.0);
  c.intensity.assign(n, 0.25f);
  return c;
}

/// A 3-scan KITTI-layout folder with labels, poses, times and calib.
void make_sequence(const TempDir& dir) {
  for (std::size_t i = 0; i < 3; ++i) {
    write_kitti_bin(dir.file("velodyne/" + scan_name(i) + ".bin"),
                    line_cloud(10 + i, static_cast<double>(i)));
    write_labels(dir.file("labels/" + scan_name(i) + ".label"),
                 std::vector<Label>(10 + i, semantic::kStatic));
  }
  write_text(dir.file("poses.txt"),
             "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n"
             "1 0 0 2 0 1 0 0 0 0 1 0\n");
  write_text(dir.file("times.txt"), "0\n0.1\n0.2\n");
  write_text(dir.file("calib.txt"), "Tr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n");
}
}  // namespace

TEST(Sequence, SmallFolderOpensAndAppliesTr) {
  TempDir dir;
  make_sequence(dir);
  const auto seq = open_sequence(dir.path.string());
  EXPECT_EQ(seq.size(), 3u);
  EXPECT_TRUE(seq.has_labels());
  ASSERT_TRUE(seq.calib.has_value());
  EXPECT_TRUE(seq.calib->has_Tr);
  EXPECT_EQ(seq.times.size(), 3u);
  const auto scan = seq.read_scan(2);
  EXPECT_EQ(scan.size(), 12u);
  EXPECT_EQ(seq.read_scan_labels(2, scan.size()).size(), 12u);
  // Camera moves +1 m along camera x per scan; camera x = -lidar y, so the LiDAR moves along -y.
  const auto lidar = seq.lidar_poses();
  EXPECT_LT((lidar[2].translation() - Vec3(0, -2, 0)).norm(), 1e-12);
}

TEST(Sequence, CountAndNameMismatchesNameTheFile) {
  {
    TempDir dir;
    make_sequence(dir);
    write_text(dir.file("poses.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
    const auto msg = input_error_of([&] { open_sequence(dir.path.string()); });
    EXPECT_THAT(msg, HasSubstr("poses.txt"));
    EXPECT_THAT(msg, HasSubstr("2 poses"));
  }
  {
    TempDir dir;
    make_sequence(dir);
    write_text(dir.file("times.txt"), "0\n0.1\n0.2\n0.3\n");
    EXPECT_THAT(input_error_of([&] { open_sequence(dir.path.string()); }), HasSubstr("times.txt"));
  }
  {
    TempDir dir;
    make_sequence(dir);
    std::filesystem::remove(dir.file("labels/000001.label"));
    EXPECT_THAT(input_error_of([&] { open_sequence(dir.path.string()); }), HasSubstr("labels"));
  }
  {
    TempDir dir;
    make_sequence(dir);
    std::filesystem::rename(dir.file("labels/000001.label"), dir.file("labels/000007.label"));
    const auto msg = input_error_of([&] { open_sequence(dir.path.string()); });
    EXPECT_THAT(msg, HasSubstr("000002.label"));  // sorted: 000000, 000002, 000007 vs scans 0, 1, 2
    EXPECT_THAT(msg, HasSubstr("000001.bin"));
  }
  {
    TempDir dir;
    make_sequence(dir);
    // Label count of one scan only shows when the scan is read.
    write_labels(dir.file("labels/000001.label"), std::vector<Label>(3, 0));
    const auto seq = open_sequence(dir.path.string());
    EXPECT_THAT(input_error_of([&] { (void)seq.read_scan_labels(1, seq.read_scan(1).size()); }),
                HasSubstr("000001.label"));
  }
  {
    TempDir dir;
    EXPECT_THAT(input_error_of([&] { open_sequence(dir.path.string()); }), HasSubstr("no scans"));
    EXPECT_THAT(input_error_of([&] { open_sequence(dir.file("absent")); }), HasSubstr("absent"));
  }
}

TEST(Sequence, FolderOfPcdFiles) {
  TempDir dir;
  write_pcd(dir.file("b.pcd"), line_cloud(7, 1.0));
  write_pcd(dir.file("a.pcd"), line_cloud(5, 0.0), Encoding::kAscii);
  write_text(dir.file("notes.txt"), "ignored\n");
  const auto seq = open_sequence(dir.path.string());
  ASSERT_EQ(seq.size(), 2u);
  EXPECT_FALSE(seq.has_labels());
  EXPECT_FALSE(seq.has_poses());
  EXPECT_EQ(seq.read_scan(0).size(), 5u);  // sorted by name
  EXPECT_EQ(seq.read_scan(1).size(), 7u);
}

TEST(Sequence, RealKittiDrive0005) {
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is absent";
  const auto seq = open_sequence(dir);
  EXPECT_EQ(seq.size(), 100u);
  EXPECT_EQ(seq.poses.size(), 100u);
  EXPECT_EQ(seq.times.size(), 100u);
  EXPECT_TRUE(seq.has_labels());
  ASSERT_TRUE(seq.calib.has_value());
  EXPECT_TRUE(seq.calib->has_Tr);
  const auto scan = seq.read_scan(0);
  EXPECT_GT(scan.size(), 100000u);
  EXPECT_LT(scan.size(), 130000u);
  EXPECT_EQ(seq.read_scan_labels(0, scan.size()).size(), scan.size());
  // The drive's reference path of scans 0..99 is 39.0 m (README); Tr does not change lengths.
  const auto lidar = seq.lidar_poses();
  double length = 0.0;
  for (std::size_t i = 1; i < lidar.size(); ++i)
    length += (lidar[i].translation() - lidar[i - 1].translation()).norm();
  EXPECT_NEAR(length, 39.0, 0.5);
  // In the LiDAR frame the car drives forward along +x.
  EXPECT_GT(lidar.back().translation().x(), 30.0);
}
