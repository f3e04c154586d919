// Malformed and unusual input for the readers: scan order and numbering, links, FIFOs and
// devices, oversized headers and files, no-return points, times and poses out of bounds, foreign
// record layouts, calib.txt without Tr.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/io/sequence_check.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

namespace {
/// A sweep in firing order (ring by ring, azimuth by azimuth), as a LiDAR writes it: neighbours
/// in the file are neighbours in space.
PointCloud ordered_sweep(int rings, int columns, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> wobble(-0.05, 0.05);
  PointCloud c;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < columns; ++k) {
      const double az = 2.0 * M_PI * k / columns, el = (-20.0 + 0.6 * r) * M_PI / 180.0;
      const double range = 12.0 + 3.0 * std::sin(3.0 * az) + wobble(rng);
      c.xyz.emplace_back(range * std::cos(el) * std::cos(az), range * std::cos(el) * std::sin(az),
                         range * std::sin(el));
      c.intensity.push_back(static_cast<float>(0.3 + 0.1 * std::sin(az)));
    }
  return c;
}

/// A KITTI folder of `n` scans named by `name(i)` (scan i lies i metres along x).
template <class Name>
void make_folder(const TempDir& dir, std::size_t n, Name&& name) {
  for (std::size_t i = 0; i < n; ++i) {
    PointCloud c = ordered_sweep(4, 64, static_cast<unsigned>(i));
    for (auto& p : c.xyz) p.x() += static_cast<double>(i);
    write_kitti_bin(dir.file("velodyne/" + name(i) + ".bin"), c);
  }
}

std::string poses_text(std::size_t n) {
  std::string text;
  for (std::size_t i = 0; i < n; ++i) text += "1 0 0 " + std::to_string(i) + " 0 1 0 0 0 0 1 0\n";
  return text;
}

template <class T>
void append(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
}  // namespace

TEST(HardeningOrder, UnpaddedScanNamesAreInNumericOrder) {
  TempDir dir;
  make_folder(dir, 12, [](std::size_t i) { return std::to_string(i); });  // 0.bin .. 11.bin
  for (std::size_t i = 0; i < 12; ++i)
    write_labels(dir.file("labels/" + std::to_string(i) + ".label"),
                 std::vector<Label>(256, semantic::kStatic));
  const Sequence seq = open_sequence(dir.path.string());
  ASSERT_EQ(seq.size(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    EXPECT_EQ(fs::path(seq.scan_files[i]).stem().string(), std::to_string(i));
    EXPECT_EQ(fs::path(seq.label_files[i]).stem().string(), std::to_string(i));
    const double x = ordered_sweep(4, 64, static_cast<unsigned>(i)).xyz.front().x() + static_cast<double>(i);
    EXPECT_NEAR(seq.read_scan(i).xyz.front().x(), x, 1e-4) << i;
  }
  // The same for a folder of PCD files.
  TempDir pcds;
  for (std::size_t i = 0; i < 11; ++i)
    write_pcd(pcds.file("cloud_" + std::to_string(i) + ".pcd"), ordered_sweep(2, 16, 1));
  const Sequence p = open_sequence(pcds.path.string());
  ASSERT_EQ(p.size(), 11u);
  EXPECT_EQ(fs::path(p.scan_files[2]).filename().string(), "cloud_2.pcd");
  EXPECT_EQ(fs::path(p.scan_files[10]).filename().string(), "cloud_10.pcd");
}

TEST(HardeningOrder, NaturalLessComparesDigitRunsByValue) {
  EXPECT_TRUE(natural_less("2.bin", "10.bin"));
  EXPECT_FALSE(natural_less("10.bin", "2.bin"));
  EXPECT_TRUE(natural_less("000009.bin", "000010.bin"));
  EXPECT_TRUE(natural_less("a2", "a10"));
  EXPECT_TRUE(natural_less("a10", "b2"));
  EXPECT_TRUE(natural_less("5.bin", "005.bin"));  // same value: fewer leading zeros first
  EXPECT_FALSE(natural_less("x", "x"));
  EXPECT_TRUE(natural_less("x", "x1"));
}

TEST(HardeningOrder, AGapInTheScanNumbersIsAnErrorWhenPosesPairByLine) {
  TempDir dir;
  make_folder(dir, 7, [](std::size_t i) { return scan_name(i); });
  fs::remove(dir.file("velodyne/000005.bin"));
  write_text(dir.file("poses.txt"), poses_text(6));
  const std::string msg = input_error_of([&] { (void)open_sequence(dir.path.string()); });
  EXPECT_THAT(msg, HasSubstr("poses.txt"));
  EXPECT_THAT(msg, HasSubstr("skip from 000004 to 000006"));
  const auto report = check_sequence(dir.path.string());
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_THAT(report.problems[0], HasSubstr("000004 to 000006"));
  // Without poses.txt / times.txt nothing pairs by position: a warning.
  fs::remove(dir.file("poses.txt"));
  const Sequence seq = open_sequence(dir.path.string());
  ASSERT_EQ(seq.warnings.size(), 1u);
  EXPECT_THAT(seq.warnings[0], HasSubstr("1 missing"));
  EXPECT_EQ(seq.output_name(5), "000006");
  // Two files with one number.
  make_folder(dir, 1, [](std::size_t) { return std::string("0"); });
  EXPECT_THAT(input_error_of([&] { (void)open_sequence(dir.path.string()); }), HasSubstr("same scan number"));
}

TEST(HardeningFiles, ASymlinkLoopIsAProblemOfItsOwnAndTheCheckGoesOn) {
  TempDir dir;
  make_folder(dir, 3, [](std::size_t i) { return scan_name(i); });
  fs::create_symlink("loop.bin", dir.file("velodyne/loop.bin"));
  SequenceReport report;
  ASSERT_NO_THROW(report = check_sequence(dir.path.string()));
  EXPECT_EQ(report.scans, 4u);
  EXPECT_EQ(report.scans_ok, 3u);
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_THAT(report.problems[0], HasSubstr("loop.bin"));
  EXPECT_THAT(input_error_of([&] { (void)open_sequence(dir.path.string()); }), HasSubstr("loop.bin"));
}

TEST(HardeningFiles, FifosDevicesAndHugeFilesAreRefusedNamingTheFile) {
  TempDir dir;
  make_folder(dir, 2, [](std::size_t i) { return scan_name(i); });
  ASSERT_EQ(::mkfifo(dir.file("poses.txt").c_str(), 0600), 0);
  const std::string fifo = input_error_of([&] { (void)open_sequence(dir.path.string()); });
  EXPECT_THAT(fifo, HasSubstr("poses.txt"));
  EXPECT_THAT(fifo, HasSubstr("FIFO"));
  fs::remove(dir.file("poses.txt"));
  fs::create_symlink("/dev/zero", dir.file("calib.txt"));
  const std::string device = input_error_of([&] { (void)open_sequence(dir.path.string()); });
  EXPECT_THAT(device, HasSubstr("calib.txt"));
  EXPECT_THAT(device, HasSubstr("device"));
}

TEST(HardeningPcd, AHeaderClaimingMorePointsThanTheFileHoldsIsTruncatedBeforeAllocating) {
  TempDir dir;
  for (const char* points : {"1000000000", "10000000000", "18446744073709551615"}) {
    const std::string head = std::string("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH ") + points +
                             "\nHEIGHT 1\nPOINTS " + points + "\n";
    write_text(dir.file("b.pcd"), head + "DATA binary\n" + std::string(1700, '\1'));
    write_text(dir.file("a.pcd"), head + "DATA ascii\n1 2 3\n");
    for (const char* name : {"b.pcd", "a.pcd"}) {
      const std::string msg = input_error_of([&] { (void)read_pcd(dir.file(name)); });
      EXPECT_THAT(msg, HasSubstr(name)) << points;
      EXPECT_THAT(msg, HasSubstr("truncated")) << points;
    }
  }
  // WIDTH * HEIGHT overflowing 64 bits.
  write_text(dir.file("o.pcd"),
             "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967296\nHEIGHT 4294967297\nDATA binary\n");
  EXPECT_THAT(input_error_of([&] { (void)read_pcd(dir.file("o.pcd")); }), HasSubstr("o.pcd"));
  // A field of COUNT 0 has no bytes to read.
  write_text(dir.file("c.pcd"), "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 0\nPOINTS 1\nDATA binary\n" +
                                    std::string(8, '\0'));
  EXPECT_THAT(input_error_of([&] { (void)read_pcd(dir.file("c.pcd")); }), HasSubstr("COUNT 0"));
  // PLY: the same for its vertex count.
  write_text(dir.file("v.ply"),
             "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n" +
                 std::string(64, '\0'));
  EXPECT_THAT(input_error_of([&] { (void)read_ply(dir.file("v.ply")); }), HasSubstr("truncated"));
}

TEST(HardeningPcd, NoReturnPointsOfAnOrganisedCloudAreDroppedAndTheirLabelsWithThem) {
  TempDir dir;
  // 2 x 3 organised cloud, the middle of each row without a return.
  const std::string pcd =
      "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\nHEIGHT 2\nPOINTS 6\nDATA ascii\n"
      "10 0 0 1\nnan nan nan 0\n0 10 0 2\n-10 0 0 3\nnan nan nan 0\n0 -10 1 4\n";
  write_text(dir.file("velodyne/000000.pcd"), pcd);
  write_labels(dir.file("labels/000000.label"), {9, 0, 251, 9, 0, 252});
  const Sequence seq = open_sequence(dir.path.string());
  ScanInfo info;
  const PointCloud cloud = seq.read_scan(0, &info);
  ASSERT_EQ(cloud.size(), 4u);
  EXPECT_EQ(info.dropped(), 2u);
  EXPECT_EQ(info.kept, (std::vector<std::size_t>{0, 2, 3, 5}));
  EXPECT_EQ(cloud.intensity, (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(seq.read_scan_labels(0, cloud.size(), &info), (std::vector<Label>{9, 251, 9, 252}));
  const auto report = check_sequence(dir.path.string());
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
  EXPECT_EQ(report.dropped_points, 2u);
  EXPECT_EQ(report.labelled_points, 4u);  // the two no-return points are labelled 0 (unlabeled)
}

TEST(HardeningPcd, NanTimesAndIntensitiesOfRealPointsAreErrors) {
  TempDir dir;
  const std::string head =
      "FIELDS x y z intensity t\nSIZE 4 4 4 4 4\nTYPE F F F F F\nWIDTH 2\nPOINTS 2\nDATA ascii\n";
  write_text(dir.file("t.pcd"), head + "1 2 3 1 0.0\n4 5 6 1 nan\n");
  EXPECT_THAT(input_error_of([&] { (void)read_pcd(dir.file("t.pcd")); }),
              HasSubstr("point 1 has a NaN or Inf time"));
  write_text(dir.file("i.pcd"), head + "1 2 3 inf 0.0\n4 5 6 1 0.5\n");
  EXPECT_THAT(input_error_of([&] { (void)read_pcd(dir.file("i.pcd")); }), HasSubstr("intensity"));
  // A double intensity outside the float range: an error, not an undefined conversion.
  std::string bin = "FIELDS x y z intensity\nSIZE 4 4 4 8\nTYPE F F F F\nWIDTH 1\nPOINTS 1\nDATA binary\n";
  append(bin, 1.0f);
  append(bin, 2.0f);
  append(bin, 3.0f);
  append(bin, 1e300);
  write_text(dir.file("d.pcd"), bin);
  EXPECT_THAT(input_error_of([&] { (void)read_pcd(dir.file("d.pcd")); }), HasSubstr("intensity"));
}

TEST(HardeningText, EqualTimesFarPosesAndBadStampsAreErrors) {
  TempDir dir;
  write_text(dir.file("times.txt"), "0.5\n0.5\n0.5\n");
  const std::string times = input_error_of([&] { (void)read_times(dir.file("times.txt")); });
  EXPECT_THAT(times, HasSubstr("times.txt:2:"));
  EXPECT_THAT(times, HasSubstr("equals"));
  write_text(dir.file("poses.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1e300 0 1 0 0 0 0 1 0\n");
  EXPECT_THAT(input_error_of([&] { (void)read_kitti_poses(dir.file("poses.txt")); }),
              HasSubstr("poses.txt:2:"));
  write_text(dir.file("tum.txt"), "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  EXPECT_THAT(input_error_of([&] { (void)read_tum_poses(dir.file("tum.txt")); }), HasSubstr("tum.txt:2:"));
  write_text(dir.file("tum2.txt"), "1 1e300 0 0 0 0 0 1\n");
  EXPECT_THAT(input_error_of([&] { (void)read_tum_poses(dir.file("tum2.txt")); }), HasSubstr("1e9 m"));
}

TEST(HardeningBin, ForeignRecordLayoutsAreRecognisedAndGenuineScansPass) {
  TempDir dir;
  const PointCloud scan = ordered_sweep(16, 256, 3);
  std::string f32, f64, five, pcl;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const float v[4] = {static_cast<float>(scan.xyz[i].x()), static_cast<float>(scan.xyz[i].y()),
                        static_cast<float>(scan.xyz[i].z()), scan.intensity[i]};
    for (float x : v) {
      append(f32, x);
      append(f64, static_cast<double>(x));
      append(five, x);
      append(pcl, x);
    }
    append(five, static_cast<float>(i / 256));      // ring
    for (int k = 0; k < 4; ++k) append(pcl, 0.0f);  // PCL's padded 32-byte PointXYZI
  }
  write_text(dir.file("f32.bin"), f32);
  EXPECT_EQ(read_kitti_bin(dir.file("f32.bin")).size(), scan.size());
  for (const auto& [name, bytes] :
       {std::pair<std::string, std::string>{"f64.bin", f64}, {"five.bin", five}, {"pcl.bin", pcl}}) {
    ASSERT_EQ(bytes.size() % 16, 0u);
    write_text(dir.file(name), bytes);
    const std::string path = dir.file(name);  // C++17 lambdas cannot capture structured bindings
    const std::string msg = input_error_of([&] { (void)read_kitti_bin(path); });
    EXPECT_THAT(msg, HasSubstr(name));
    EXPECT_THAT(msg, HasSubstr("does not look like float32 x y z intensity records"));
  }
  // A scan in no particular order, all points equal, or a single point passes.
  PointCloud shuffled = scan;
  std::shuffle(shuffled.xyz.begin(), shuffled.xyz.end(), std::mt19937(5));
  write_kitti_bin(dir.file("shuffled.bin"), shuffled);
  EXPECT_EQ(read_kitti_bin(dir.file("shuffled.bin")).size(), scan.size());
  PointCloud same;
  same.xyz.assign(300, Vec3(5.0, 1.0, 0.5));
  write_kitti_bin(dir.file("same.bin"), same);
  EXPECT_EQ(read_kitti_bin(dir.file("same.bin")).size(), 300u);
  // Every scan of the real drive passes.
  const std::string data = std::string(DLOAM_KITTI_0005) + "/velodyne";
  if (!fs::exists(data)) return;
  for (const auto& entry : fs::directory_iterator(data))
    EXPECT_NO_THROW((void)read_kitti_bin(entry.path().string()));
}

TEST(HardeningBin, PointsFartherThanAMillionMetresAreErrors) {
  TempDir dir;
  PointCloud c = ordered_sweep(2, 8, 1);
  c.xyz[3] = Vec3(1e30, 0, 0);
  write_kitti_bin(dir.file("far.bin"), c);
  const std::string msg = input_error_of([&] { (void)read_kitti_bin(dir.file("far.bin")); });
  EXPECT_THAT(msg, HasSubstr("far.bin"));
  EXPECT_THAT(msg, HasSubstr("point 3"));
}

TEST(HardeningCalib, TrUnderItsObjectDetectionNameAndCalibWithoutTrBesidePoses) {
  TempDir dir;
  write_text(dir.file("c1.txt"), "Tr_velo_to_cam: 0 -1 0 0 0 0 -1 0 1 0 0 0\n");
  const Calib c1 = read_calib(dir.file("c1.txt"));
  EXPECT_TRUE(c1.has_Tr);
  write_calib(dir.file("c2.txt"), c1);  // written back as Tr, once
  EXPECT_TRUE(read_calib(dir.file("c2.txt")).has_Tr);
  write_text(dir.file("c3.txt"), "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\nTr_velo_to_cam: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_THAT(input_error_of([&] { (void)read_calib(dir.file("c3.txt")); }), HasSubstr("duplicate key"));

  // Camera-frame ground truth would be taken as LiDAR-frame: refused, naming calib.txt.
  make_folder(dir, 3, [](std::size_t i) { return scan_name(i); });
  write_text(dir.file("poses.txt"), poses_text(3));
  for (const char* calib : {"P0: 1 0 0 0 0 1 0 0 0 0 1 0\n", ""}) {
    write_text(dir.file("calib.txt"), calib);
    const Sequence seq = open_sequence(dir.path.string());
    EXPECT_TRUE(seq.poses_frame_unknown());
    const std::string msg = input_error_of([&] { (void)seq.lidar_poses(); });
    EXPECT_THAT(msg, HasSubstr("calib.txt"));
    EXPECT_THAT(msg, HasSubstr("no Tr"));
    const auto report = check_sequence(dir.path.string());
    ASSERT_EQ(report.problems.size(), 1u);
    EXPECT_THAT(report.problems[0], HasSubstr("no Tr"));
  }
}
