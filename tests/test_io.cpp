// KITTI file formats: round trips and every bad-input case (exception type + file name).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "dloam/io/kitti.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;

namespace {
PointCloud sample_cloud(std::size_t n) {
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.37 * static_cast<double>(i);
    c.xyz.emplace_back(10.0 * std::cos(a), 10.0 * std::sin(a), -1.5 + 0.01 * static_cast<double>(i));
    c.intensity.push_back(static_cast<float>(i % 100) / 100.0f);
  }
  return c;
}

Pose sample_pose(double k) {
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(0.3 * k, Vec3::UnitZ()) * Eigen::AngleAxisd(0.05 * k, Vec3::UnitX()))
                   .toRotationMatrix();
  p.translation() = Vec3(1.5 * k, -0.25 * k, 0.01 * k);
  return p;
}

void write_raw_floats(const std::string& path, const std::vector<float>& v) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * 4));
}
}  // namespace

TEST(KittiBin, RoundTripKeepsFloat32Values) {
  TempDir dir;
  const auto cloud = sample_cloud(1000);
  write_kitti_bin(dir.file("a.bin"), cloud);
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.bin.tmp")));
  EXPECT_EQ(std::filesystem::file_size(dir.file("a.bin")), 16000u);
  const auto back = read_kitti_bin(dir.file("a.bin"));
  ASSERT_EQ(back.size(), cloud.size());
  ASSERT_TRUE(back.has_intensity());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_LT((back.xyz[i] - cloud.xyz[i]).norm(), 1e-5);
    EXPECT_EQ(back.intensity[i], cloud.intensity[i]);
  }
}

TEST(KittiBin, RejectsMissingTruncatedEmptyNanInf) {
  TempDir dir;
  EXPECT_THAT(input_error_of([&] { read_kitti_bin(dir.file("missing.bin")); }), HasSubstr("missing.bin"));

  write_raw_floats(dir.file("trunc.bin"), {1, 2, 3, 4, 5, 6});  // 24 bytes
  const auto trunc = input_error_of([&] { read_kitti_bin(dir.file("trunc.bin")); });
  EXPECT_THAT(trunc, HasSubstr("trunc.bin"));
  EXPECT_THAT(trunc, HasSubstr("multiple of 16"));

  write_raw_floats(dir.file("empty.bin"), {});
  const auto empty = input_error_of([&] { read_kitti_bin(dir.file("empty.bin")); });
  EXPECT_THAT(empty, HasSubstr("empty.bin"));
  EXPECT_THAT(empty, HasSubstr("empty"));

  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  write_raw_floats(dir.file("nan.bin"), {1, 2, 3, 0, 4, nan, 6, 0});
  const auto nan_msg = input_error_of([&] { read_kitti_bin(dir.file("nan.bin")); });
  EXPECT_THAT(nan_msg, HasSubstr("nan.bin"));
  EXPECT_THAT(nan_msg, HasSubstr("point 1 "));

  write_raw_floats(dir.file("inf.bin"), {1, 2, 3, 0, 4, 5, 6, 0, -inf, 1, 1, 0});
  const auto inf_msg = input_error_of([&] { read_kitti_bin(dir.file("inf.bin")); });
  EXPECT_THAT(inf_msg, HasSubstr("inf.bin"));
  EXPECT_THAT(inf_msg, HasSubstr("point 2 "));
}

TEST(Labels, RoundTripAndCountMismatch) {
  TempDir dir;
  std::vector<Label> labels;
  for (Label i = 0; i < 500; ++i)
    labels.push_back(semantic::make(i % 3 ? semantic::kStatic : semantic::kMovingCar, i / 7));
  write_labels(dir.file("a.label"), labels);
  EXPECT_EQ(read_labels(dir.file("a.label"), 500), labels);
  const auto msg = input_error_of([&] { read_labels(dir.file("a.label"), 501); });
  EXPECT_THAT(msg, HasSubstr("a.label"));
  EXPECT_THAT(msg, HasSubstr("500 labels"));
  EXPECT_THAT(input_error_of([&] { read_labels(dir.file("none.label"), 1); }), HasSubstr("none.label"));
}

TEST(KittiPoses, RoundTripAndLineErrors) {
  TempDir dir;
  std::vector<Pose> poses;
  for (int k = 0; k < 20; ++k) poses.push_back(sample_pose(k));
  write_kitti_poses(dir.file("poses.txt"), poses);
  const auto back = read_kitti_poses(dir.file("poses.txt"));
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i)
    EXPECT_LT((back[i].matrix() - poses[i].matrix()).cwiseAbs().maxCoeff(), 1e-8);

  write_text(dir.file("short.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  const auto short_msg = input_error_of([&] { read_kitti_poses(dir.file("short.txt")); });
  EXPECT_THAT(short_msg, HasSubstr("short.txt:2:"));
  EXPECT_THAT(short_msg, HasSubstr("12 numbers"));

  write_text(dir.file("word.txt"), "1 0 0 0 0 1 0 0 0 0 1 zero\n");
  EXPECT_THAT(input_error_of([&] { read_kitti_poses(dir.file("word.txt")); }), HasSubstr("word.txt:1:"));

  write_text(dir.file("scaled.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n");
  const auto rot_msg = input_error_of([&] { read_kitti_poses(dir.file("scaled.txt")); });
  EXPECT_THAT(rot_msg, HasSubstr("scaled.txt:2:"));
  EXPECT_THAT(rot_msg, HasSubstr("orthonormal"));

  write_text(dir.file("mirror.txt"), "-1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_THAT(input_error_of([&] { read_kitti_poses(dir.file("mirror.txt")); }), HasSubstr("mirror.txt:1:"));
}

TEST(TumPoses, RoundTripAndBadQuaternion) {
  TempDir dir;
  std::vector<StampedPose> poses;
  for (int k = 0; k < 10; ++k) poses.push_back({0.1 * k + 1e9, sample_pose(k)});
  write_tum_poses(dir.file("tum.txt"), poses);
  const auto back = read_tum_poses(dir.file("tum.txt"));
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(back[i].t, poses[i].t, 1e-6);
    EXPECT_LT((back[i].pose.matrix() - poses[i].pose.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  }
  write_text(dir.file("badq.txt"), "# t x y z qx qy qz qw\n0 1 2 3 0 0 0 2\n");
  const auto msg = input_error_of([&] { read_tum_poses(dir.file("badq.txt")); });
  EXPECT_THAT(msg, HasSubstr("badq.txt:2:"));
  EXPECT_THAT(msg, HasSubstr("quaternion"));
}

TEST(Calib, RoundTripAndMalformedLines) {
  TempDir dir;
  Calib calib;
  calib.entries.push_back({"P0", std::vector<double>(12, 0.5)});
  calib.Tr = sample_pose(2.0);
  calib.has_Tr = true;
  write_calib(dir.file("calib.txt"), calib);
  const auto back = read_calib(dir.file("calib.txt"));
  ASSERT_TRUE(back.has_Tr);
  EXPECT_LT((back.Tr.matrix() - calib.Tr.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  ASSERT_EQ(back.entries.size(), 2u);
  EXPECT_EQ(back.entries[0].first, "P0");
  EXPECT_EQ(back.entries[0].second, calib.entries[0].second);
  EXPECT_EQ(back.entries[1].first, "Tr");

  write_text(dir.file("nocolon.txt"), "P0: 1 2 3 4 5 6 7 8 9 10 11 12\nTr 1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_THAT(input_error_of([&] { read_calib(dir.file("nocolon.txt")); }), HasSubstr("nocolon.txt:2:"));
  write_text(dir.file("tr11.txt"), "Tr: 1 0 0 0 0 1 0 0 0 0 1\n");
  const auto msg = input_error_of([&] { read_calib(dir.file("tr11.txt")); });
  EXPECT_THAT(msg, HasSubstr("tr11.txt:1:"));
  EXPECT_THAT(msg, HasSubstr("12 values"));
  write_text(dir.file("word.txt"), "P0: 1 2 x\n");
  EXPECT_THAT(input_error_of([&] { read_calib(dir.file("word.txt")); }), HasSubstr("word.txt:1:"));
}

TEST(Times, RoundTripAndDecreasingTime) {
  TempDir dir;
  const std::vector<double> times{0.0, 0.1, 0.2, 0.30000001, 1234567.125};
  write_times(dir.file("times.txt"), times);
  EXPECT_EQ(read_times(dir.file("times.txt")), times);
  write_text(dir.file("back.txt"), "0.0\n0.2\n0.1\n");
  EXPECT_THAT(input_error_of([&] { read_times(dir.file("back.txt")); }), HasSubstr("back.txt:3:"));
}

TEST(Frames, CameraToLidarIsTrInvPTrAndInverts) {
  const Pose Tr = sample_pose(3.0);
  std::vector<Pose> cam{sample_pose(1.0), sample_pose(-2.0)};
  const auto lidar = camera_to_lidar(cam, Tr);
  for (std::size_t i = 0; i < cam.size(); ++i) {
    const Eigen::Matrix4d expected = Tr.matrix().inverse() * cam[i].matrix() * Tr.matrix();
    EXPECT_LT((lidar[i].matrix() - expected).cwiseAbs().maxCoeff(), 1e-12);
  }
  const auto again = lidar_to_camera(lidar, Tr);
  for (std::size_t i = 0; i < cam.size(); ++i)
    EXPECT_LT((again[i].matrix() - cam[i].matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Names, ScanNameIsSixDigits) {
  EXPECT_EQ(scan_name(42), "000042");
  EXPECT_EQ(scan_name(1234567), "1234567");
}
