// `dloam run / check / convert` on recordings: ROS 2 bags of the real KITTI scans (written by the
// rosbag2 and MCAP writers) give the folder's poses; the sensors folder's captures and bags run,
// check and convert with the sensor model they carry; bad recordings fail with clear messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_util.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr double kStamp0 = 1317000000.25;
constexpr std::size_t kScans = 10;
const std::string kSensors = DLOAM_SENSORS_DIR;

std::vector<Pose> lidar_poses(const std::string& poses_file, const io::Sequence& folder, bool camera) {
  const auto poses = io::read_kitti_poses(poses_file);
  return camera ? io::camera_to_lidar(poses, folder.calib->Tr) : poses;
}

/// The first scans of the real drive as PointCloud2 messages (float32 x y z intensity, stamps
/// from times.txt) in a rosbag2 SQLite bag and in chunked MCAP files (zstd, lz4): each run gives
/// the folder's poses (same clouds, deterministic pipeline).
TEST(RecordingCli, RunOnRos2BagsOfRealScansGivesTheFolderPoses) {
  const std::string data = DLOAM_KITTI_0005;
  if (!fs::exists(data + "/velodyne/000000.bin")) GTEST_SKIP() << "no " << data;
  TempDir dir;
  const io::Sequence folder = io::open_sequence(data);
  std::vector<std::vector<std::uint8_t>> messages;
  std::vector<std::int64_t> stamps;
  for (std::size_t i = 0; i < kScans; ++i) {
    const double stamp = kStamp0 + folder.times[i];
    messages.push_back(io::encode_pointcloud2(folder.read_scan(i), stamp, "velodyne"));
    stamps.push_back(static_cast<std::int64_t>(std::llround(stamp * 1e9)));
  }
  const std::string db3 = dir.file("kitti_db3");
  {
    io::Rosbag2Writer w(db3);
    w.add_topic("/kitti/velo/pointcloud", io::kPointCloud2Type);
    for (std::size_t i = 0; i < kScans; ++i)
      w.write("/kitti/velo/pointcloud", stamps[i], messages[i].data(), messages[i].size());
    w.close();
  }
  std::vector<std::string> bags = {db3};
  for (const char* compression : {"zstd", "lz4"}) {
    const std::string path = dir.file(std::string("kitti_") + compression + ".mcap");
    io::McapWriterOptions o;
    o.compression = compression;
    o.chunk_size = 1 << 20;  // several chunks
    io::McapWriter w(path, o);
    const auto channel =
        w.add_channel("/kitti/velo/pointcloud", "cdr",
                      w.add_schema(io::kPointCloud2Type, "ros2msg", io::pointcloud2_definition()));
    for (std::size_t i = 0; i < kScans; ++i)
      w.write(channel, static_cast<std::uint64_t>(stamps[i]), messages[i].data(), messages[i].size());
    w.close();
    bags.push_back(path);
  }
  const std::string config = std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";
  const std::string options = " --config " + config + " --detector geometric";
  const CliRun from_folder = run_dloam("run " + data + " --count " + std::to_string(kScans) + " --out " +
                                       dir.file("folder") + options);
  ASSERT_EQ(from_folder.status, 0) << from_folder.output;
  const auto want = lidar_poses(dir.file("folder/poses.txt"), folder, true);
  ASSERT_EQ(want.size(), kScans);
  EXPECT_GT(want.back().translation().norm(), 1.0);  // the car moved: a real comparison
  for (const auto& bag : bags) {
    const std::string out = dir.file("out_" + fs::path(bag).filename().string());
    const CliRun run = run_dloam("run " + bag + " --out " + out + options);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_THAT(run.output, HasSubstr("topic /kitti/velo/pointcloud"));
    const auto got = lidar_poses(out + "/poses.txt", folder, false);  // no calib: LiDAR frame
    ASSERT_EQ(got.size(), kScans) << bag;
    for (std::size_t i = 0; i < kScans; ++i)
      EXPECT_LT((got[i].matrix() - want[i].matrix()).cwiseAbs().maxCoeff(), 1e-6) << bag << " scan " << i;
    const auto tum = io::read_tum_poses(out + "/poses_tum.txt");
    ASSERT_EQ(tum.size(), kScans);
    EXPECT_NEAR(tum.back().t, kStamp0 + folder.times[kScans - 1], 1e-6) << bag;
  }
}

/// Every capture and bag of the sensors folder passes `dloam check` with the options it needs
/// (only the OS-1-64 fw 2.0 capture names its JSON differently).
TEST(RecordingCli, CheckReadsEveryRecordingOfTheSensorsFolder) {
  if (!fs::exists(kSensors + "/README.md")) GTEST_SKIP() << "no " << kSensors;
  std::vector<std::string> recordings;
  for (const auto& e : fs::recursive_directory_iterator(kSensors)) {
    const std::string p = e.path().string();
    if (e.path().extension() == ".pcap" && p.find("empty_pcap") == std::string::npos) recordings.push_back(p);
    if (e.is_directory() && fs::exists(e.path() / "metadata.yaml")) recordings.push_back(p);
  }
  std::sort(recordings.begin(), recordings.end());
  ASSERT_EQ(recordings.size(), 25u);  // 15 pcaps (without the empty one), 10 nebula bags
  for (const auto& r : recordings) {
    std::string extra;
    if (r.find("OS-1-64_1024x10_fw20") != std::string::npos)
      extra = " --metadata " + kSensors + "/ouster/OS-1-64_sensor_config_reduced.json";
    const CliRun check = run_dloam("check " + r + extra);
    EXPECT_EQ(check.status, 0) << r << "\n" << check.output;
    EXPECT_THAT(check.output, HasSubstr("decoded from raw packets")) << r;
    EXPECT_THAT(check.output, HasSubstr("sensor model")) << r;
  }
  const CliRun empty = run_dloam("check " + kSensors + "/ouster/bad/empty_pcap.pcap");
  EXPECT_EQ(empty.status, 1);
  EXPECT_THAT(empty.output, HasSubstr("empty_pcap.pcap: holds no UDP datagrams"));
}

/// The VeloView VLP-16 capture runs with no preset: the sensor model comes from the packets.
TEST(RecordingCli, RunAndConvertACaptureWithTheSensorModelItCarries) {
  const std::string pcap = kSensors + "/velodyne/veloview/vlp-16-test-90deg-1-50-frames.pcap";
  if (!fs::exists(pcap)) GTEST_SKIP() << "no " << pcap;
  TempDir dir;
  const CliRun run = run_dloam("run " + pcap + " --count 8 --detector geometric --out " + dir.file("run"));
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("sensor model from the recording: VLP-16 (16 beams"));
  EXPECT_EQ(io::read_kitti_poses(dir.file("run/poses.txt")).size(), 8u);
  // The written config records the recording's sensor model.
  std::ifstream config(dir.file("run/config.yaml"));
  const std::string text((std::istreambuf_iterator<char>(config)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("N_scan: 16"));

  const CliRun convert = run_dloam("convert " + pcap + " --count 5 --out " + dir.file("pcd"));
  ASSERT_EQ(convert.status, 0) << convert.output;
  const io::Sequence written = io::open_sequence(dir.file("pcd"));
  const io::Sequence original = io::open_sequence(pcap);
  ASSERT_EQ(written.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const PointCloud a = written.read_scan(i), b = original.read_scan(i);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); k += 97)
      EXPECT_LT((a.xyz[k] - b.xyz[k]).norm(), 1e-6);  // float32 on disk
    ASSERT_TRUE(a.has_time());
    EXPECT_NEAR(written.times[i], original.times[i] - original.times[0], 1e-6);
  }
  EXPECT_TRUE(fs::exists(dir.file("pcd/sensor.yaml")));
  const CliRun with_sensor = run_dloam("check " + dir.file("pcd"));
  EXPECT_EQ(with_sensor.status, 0) << with_sensor.output;
  const CliRun kitti = run_dloam("convert " + pcap + " --count 3 --format kitti --out " + dir.file("kitti"));
  ASSERT_EQ(kitti.status, 0) << kitti.output;
  EXPECT_TRUE(fs::exists(dir.file("kitti/velodyne/000002.bin")));
  EXPECT_EQ(io::read_times(dir.file("kitti/times.txt")).size(), 3u);
}

TEST(RecordingCli, BadRecordingsFailWithTheFileAndTheProblem) {
  TempDir dir;
  write_text(dir.file("notes.pcap"), "not a capture\n");
  CliRun r = run_dloam("run " + dir.file("notes.pcap") + " --out " + dir.file("o"));
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr(dir.file("notes.pcap") + ": not a readable pcap or pcapng capture"));
  write_text(dir.file("x.mcap"), "\x89MCAP0\r\n garbage");
  r = run_dloam("check " + dir.file("x.mcap"));
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr(dir.file("x.mcap") + ": record header at byte 8"));
  const std::string pcap = kSensors + "/velodyne/rust-lidar-utils/velodyne_example.pcap";
  if (!fs::exists(pcap)) GTEST_SKIP() << "no " << pcap;
  const std::string fw20 = kSensors + "/ouster/OS-1-64_1024x10_fw20.pcap";  // its JSON has another name
  r = run_dloam("check " + fw20);
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output,
              HasSubstr(fw20 + ": holds Ouster packets, which cannot be decoded without the sensor's "
                               "metadata JSON"));
  r = run_dloam("check " + pcap + " --port 7502");
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr(pcap + ": no UDP datagrams to port 7502 (2368: 84 datagrams)"));
  r = run_dloam("check " + pcap + " --metadata " + kSensors + "/ouster/OS-1-32-G_v2.1.1_1024x10.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output,
              HasSubstr("--metadata is the Ouster sensor JSON, but the recording holds Velodyne packets"));
}

}  // namespace
}  // namespace dloam
