// Recordings on unusual input: PointCloud2 values no LiDAR gives (ROS 2 bags share the ROS 1
// checks), calibration and metadata files that are FIFOs or devices, and the inputs the fuzz
// harnesses of the recording readers found.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "dloam/drivers/ouster_metadata.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "dloam/io/pointcloud2_fields.hpp"
#include "test_io_util.hpp"

namespace dloam::test {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kSensors = DLOAM_SENSORS_DIR;

PointCloud small_cloud() {
  PointCloud cloud;
  for (int i = 0; i < 8; ++i) {
    cloud.xyz.emplace_back(5.0 + i, 1.0, -1.0);
    cloud.intensity.push_back(0.5f);
    cloud.time.push_back(static_cast<float>(i) / 8.0f);
  }
  return cloud;
}

std::string cdr_error(const PointCloud& cloud) {
  const auto bytes = io::encode_pointcloud2(cloud, 10.0, "lidar");
  return input_error_of([&] { (void)io::read_pointcloud2(bytes.data(), bytes.size(), "b.mcap: message 3"); });
}
}  // namespace

TEST(HardeningRecordings, PointCloud2ValuesOutOfRangeAreErrors) {
  const PointCloud good = small_cloud();
  const auto bytes = io::encode_pointcloud2(good, 10.0, "lidar");
  EXPECT_EQ(io::read_pointcloud2(bytes.data(), bytes.size(), "ok").cloud.size(), good.size());

  PointCloud far = good;
  far.xyz[3].x() = 1e7;
  EXPECT_THAT(cdr_error(far), HasSubstr("b.mcap: message 3: point 3 is farther than 1e6 m"));
  PointCloud nan_time = good;
  nan_time.time[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THAT(cdr_error(nan_time), HasSubstr("point 5 has a NaN or Inf time"));
  PointCloud inf_intensity = good;
  inf_intensity.intensity[2] = std::numeric_limits<float>::infinity();
  EXPECT_THAT(cdr_error(inf_intensity), HasSubstr("point 2 has intensity"));

  // A layout of zero-byte points claiming 4 billion of them: an error, not a 4-billion-point
  // allocation.
  io::CloudView view;
  view.height = 1;
  view.width = 4000000000u;
  view.point_step = 0;
  view.row_step = 0;
  view.fields = {{"x", 0, 7, 1}, {"y", 0, 7, 1}, {"z", 0, 7, 1}};
  const std::uint8_t data[4] = {0, 0, 0, 0};
  view.data = data;
  view.size = sizeof(data);
  EXPECT_THAT(input_error_of([&] { (void)io::convert_cloud(view, "m"); }), HasSubstr("m: point_step 0"));
}

TEST(HardeningRecordings, CalibrationFilesThatAreNotRegularFilesAreRefused) {
  const std::string pcap = kSensors + "/velodyne/rust-lidar-utils/velodyne_vlp16.pcap";
  if (!fs::exists(pcap)) GTEST_SKIP() << "shared sensor data not found: " << pcap;
  TempDir dir;
  ASSERT_EQ(::mkfifo(dir.file("calib.yaml").c_str(), 0600), 0);
  io::InputOptions fifo;
  fifo.calibration = dir.file("calib.yaml");
  const std::string f = input_error_of([&] { (void)io::open_sequence(pcap, fifo); });
  EXPECT_THAT(f, HasSubstr("calib.yaml"));
  EXPECT_THAT(f, HasSubstr("FIFO"));
  io::InputOptions device;
  device.calibration = "/dev/zero";
  EXPECT_THAT(input_error_of([&] { (void)io::open_sequence(pcap, device); }),
              HasSubstr("/dev/zero: is a device"));
  io::InputOptions missing;
  missing.metadata = dir.file("none.json");
  EXPECT_THAT(input_error_of([&] { (void)io::open_sequence(pcap, missing); }),
              HasSubstr("none.json: file not found"));
}

TEST(HardeningRecordings, OusterMetadataWithANumberBeyondDoubleIsAnError) {
  // Found by fuzz/fuzz_ouster_metadata.cpp: nlohmann::json's out_of_range (406) for a number
  // that overflows a double escaped the reader.
  const std::string json =
      "{\n  \"base_pn\": \"830-101845-E\",\n  \"beam_altitude_angles\": [12.75, 10.03, "
      "4444444444444444444444444E444444444444444444444444444444444444444444444444444444444444444, 3.41]\n}\n";
  const std::string msg = input_error_of([&] { (void)drivers::parse_ouster_metadata(json, "os.json"); });
  EXPECT_THAT(msg, HasSubstr("os.json: not valid JSON"));
  EXPECT_THAT(msg, HasSubstr("number overflow"));
}

TEST(HardeningRecordings, OusterMetadataWithLongRunsOfDigitsIsReadOrAnError) {
  // Found by fuzz/fuzz_ouster_metadata.cpp: the beams of a product line and the firmware version
  // were read with std::stoi, whose out_of_range escaped the reader for 20 digits.
  auto with = [](const std::string& fields) {
    return "{" + fields + R"(, "beam_altitude_angles": [1.5, -1.5], "beam_azimuth_angles": [0, 0]})";
  };
  const std::string many(20, '9');
  EXPECT_THAT(input_error_of([&] {
                (void)drivers::parse_ouster_metadata(
                    with(R"("prod_line": "OS-1-)" + many + R"(", "lidar_mode": "1024x10")"), "os.json");
              }),
              HasSubstr("os.json: beam_altitude_angles: has 2 beams but prod_line is OS-1-999"));
  const auto md = drivers::parse_ouster_metadata(
      with(R"("build_rev": "v)" + many + R"(.0.1", "lidar_mode": "512x20")"), "os.json");
  EXPECT_EQ(md.firmware, "v" + many + ".0.1");
  EXPECT_GE(md.firmware_major, 3);
  EXPECT_EQ(md.columns_per_frame, 512);
  EXPECT_EQ(md.fps, 20.0);
  // 60,000 digits: read in one pass (a recursive matcher would overflow the stack here).
  const std::string long_run(60000, '7');
  const auto md2 = drivers::parse_ouster_metadata(
      with(R"("build_rev": "v1.)" + long_run + R"(", "image_rev": "v2.4.6", "lidar_mode": "2048x10")"),
      "os.json");
  EXPECT_EQ(md2.firmware, "v2.4.6");
  EXPECT_EQ(md2.firmware_major, 2);
  for (const std::string& mode :
       std::vector<std::string>{"1x10", "123456x10", "1024x1000", "1024x", "1024x10 ", many + "x10"})
    EXPECT_THAT(input_error_of([&] {
                  (void)drivers::parse_ouster_metadata(with(R"("lidar_mode": ")" + mode + "\""), "os.json");
                }),
                HasSubstr("os.json: lidar_mode: expected COLUMNSxRATE"))
        << mode;
}

}  // namespace dloam::test
