// `dloam check`: synthetic scans, the real drive, and a broken copy of it (the exit status and
// output must name the broken files).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "cli_util.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/sequence_check.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::CliRun;
using dloam::test::run_dloam;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {
/// One sweep of `s`: every beam at 1000 azimuths, ranges 5-60 m, 0.02 deg elevation noise.
PointCloud synthetic_sweep(const SensorConfig& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> range(5.0, 60.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  PointCloud c;
  for (int row = 0; row < s.N_scan; ++row)
    for (int k = 0; k < 1000; ++k) {
      const double az = 2.0 * M_PI * k / 1000.0, el = (s.beam_elevation_deg(row) + noise(rng)) * M_PI / 180.0;
      const double r = range(rng);
      c.xyz.emplace_back(r * std::cos(el) * std::cos(az), r * std::cos(el) * std::sin(az), r * std::sin(el));
    }
  c.intensity.assign(c.size(), 0.5f);
  return c;
}

}  // namespace

TEST(SequenceCheck, CollectsEveryProblemNamingItsFile) {
  TempDir dir;
  std::mt19937 rng(1);
  const auto vlp = sensor_preset("VLP-16");
  for (std::size_t i = 0; i < 4; ++i) {
    const auto scan = synthetic_sweep(vlp, rng);
    write_kitti_bin(dir.file("velodyne/" + scan_name(i) + ".bin"), scan);
    std::vector<Label> labels(scan.size(), semantic::kStatic);
    for (std::size_t k = 0; k < 100; ++k) labels[k] = semantic::kMovingCar;
    write_labels(dir.file("labels/" + scan_name(i) + ".label"), labels);
  }
  write_text(dir.file("times.txt"), "0\n0.1\n0.2\n0.3\n");
  auto report = check_sequence(dir.path.string());
  EXPECT_TRUE(report.problems.empty());
  EXPECT_EQ(report.scans_ok, 4u);
  EXPECT_EQ(report.moving_points, 400u);
  EXPECT_EQ(report.labelled_points, 4u * 16000u);
  ASSERT_TRUE(report.sensor.has_value()) << report.sensor_error;
  EXPECT_EQ(report.sensor->sensor.N_scan, 16);
  EXPECT_EQ(nearest_preset(report.sensor->sensor).preset, "VLP-16");

  // Break three files: it must report all three, not stop at the first.
  write_text(dir.file("velodyne/000001.bin"), "0123456789");
  write_labels(dir.file("labels/000002.label"), {1, 2, 3});
  write_text(dir.file("times.txt"), "0\n0.1\n0.2\n");
  std::vector<std::string> seen;
  report = check_sequence(dir.path.string(), [&](const std::string& p) { seen.push_back(p); });
  ASSERT_EQ(report.problems.size(), 3u);
  EXPECT_EQ(seen, report.problems);
  EXPECT_THAT(report.problems[0], HasSubstr("000001.bin"));
  EXPECT_THAT(report.problems[1], HasSubstr("000002.label"));
  EXPECT_THAT(report.problems[2], HasSubstr("times.txt"));
  EXPECT_EQ(report.scans_ok, 3u);

  const auto missing = check_sequence(dir.file("nothing-here"));
  ASSERT_EQ(missing.problems.size(), 1u);
  EXPECT_THAT(missing.problems[0], HasSubstr("nothing-here"));
}

TEST(CheckCli, RealDrivePassesAndABrokenCopyFails) {
  const std::string data = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(data)) GTEST_SKIP() << data << " is absent";
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  const CliRun ok = run_dloam("check " + data);
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_THAT(ok.output, HasSubstr("100 KITTI .bin files, 100 readable"));
  EXPECT_THAT(ok.output, HasSubstr("HDL-64E"));
  EXPECT_THAT(ok.output, HasSubstr("OK"));

  // A copy of the first 5 scans with a truncated scan, a label file for another scan and 5 poses.
  TempDir dir;
  namespace fs = std::filesystem;
  fs::create_directories(dir.path / "velodyne");
  fs::create_directories(dir.path / "labels");
  for (std::size_t i = 0; i < 5; ++i) {
    const std::string n = scan_name(i);
    fs::copy_file(data + "/velodyne/" + n + ".bin", dir.path / "velodyne" / (n + ".bin"));
    fs::copy_file(data + "/labels/" + n + ".label", dir.path / "labels" / (n + ".label"));
  }
  fs::resize_file(dir.path / "velodyne/000003.bin", fs::file_size(dir.path / "velodyne/000003.bin") - 7);
  fs::copy_file(data + "/labels/000004.label", dir.path / "labels/000001.label",
                fs::copy_options::overwrite_existing);
  fs::copy_file(data + "/calib.txt", dir.path / "calib.txt");
  fs::copy_file(data + "/poses.txt", dir.path / "poses.txt");  // 100 poses for 5 scans
  const CliRun bad = run_dloam("check " + dir.path.string());
  EXPECT_NE(bad.status, 0) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("000003.bin"));
  EXPECT_THAT(bad.output, HasSubstr("000001.label"));
  EXPECT_THAT(bad.output, HasSubstr("poses.txt"));
  EXPECT_THAT(bad.output, Not(HasSubstr("000002.bin")));
  EXPECT_THAT(bad.output, HasSubstr("FAILED: 3 problems"));
}

TEST(CheckCli, UnknownPresetAndMissingFolderFail) {
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  const CliRun missing = run_dloam("check " + dir.file("absent"));
  EXPECT_NE(missing.status, 0);
  EXPECT_THAT(missing.output, HasSubstr("absent"));
  const CliRun preset = run_dloam("check " + dir.path.string() + " --preset HDL-99");
  EXPECT_NE(preset.status, 0);
  EXPECT_THAT(preset.output, HasSubstr("HDL-99"));
}

TEST(ConfigCli, DumpPrintsLoadableYamlAndRejectsTypos) {
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  const CliRun dump = run_dloam("config dump --preset VLP-16");
  ASSERT_EQ(dump.status, 0) << dump.output;
  EXPECT_THAT(dump.output, HasSubstr("preset: VLP-16"));
  EXPECT_THAT(dump.output, HasSubstr("mapping:"));
  write_text(dir.file("mine.yaml"), "mapping: {every_n_scans: 5}\n");
  const CliRun layered =
      run_dloam("config dump --preset VLP-16 --config " + dir.file("mine.yaml") + " --section mapping");
  ASSERT_EQ(layered.status, 0) << layered.output;
  EXPECT_THAT(layered.output, HasSubstr("every_n_scans: 5"));
  EXPECT_THAT(layered.output, Not(HasSubstr("sensor:")));
  write_text(dir.file("typo.yaml"), "maping: {every_n_scans: 5}\n");
  const CliRun typo = run_dloam("config dump --config " + dir.file("typo.yaml"));
  EXPECT_NE(typo.status, 0);
  EXPECT_THAT(typo.output, HasSubstr("typo.yaml"));
  EXPECT_THAT(typo.output, HasSubstr("maping"));
}

TEST(RunCli, AWrongSensorModelStopsTheRunNamingTheScan) {
  const std::string data = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(data)) GTEST_SKIP() << data << " is absent";
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  // HDL-64E scans (-24.9 .. +2 deg) read as a VLP-16 (-15 .. +15 deg).
  const CliRun wrong = run_dloam("run " + data + " --out " + dir.file("vlp") + " --preset VLP-16 --count 2");
  EXPECT_NE(wrong.status, 0) << wrong.output;
  EXPECT_THAT(wrong.output, HasSubstr("000000.bin"));
  EXPECT_THAT(wrong.output, HasSubstr("vertical field of view"));
  // The KITTI beam table (beam origins 0.12 / 0.20 m above the sensor origin) fits the same scans.
  const CliRun right =
      run_dloam("run " + data + " --out " + dir.file("kitti") + " --config " + std::string(DLOAM_SOURCE_DIR) +
                "/config/kitti-raw.yaml --count 2 --detector none");
  EXPECT_EQ(right.status, 0) << right.output;
}

TEST(SimulateCli, SimulatesTheSensorOfAConfigFile) {
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  // The sensor section of the file is simulated, over --preset (HDL-64E: down to -24.9 deg).
  write_text(dir.file("mine.yaml"), "sensor: {preset: VLP-16, max_range: 30.0}\n");
  const CliRun mine = run_dloam("simulate --scenario urban --frames 1 --seed 3 --config " +
                                dir.file("mine.yaml") + " --out " + dir.file("mine"));
  ASSERT_EQ(mine.status, 0) << mine.output;
  const auto scan = dloam::io::read_kitti_bin(dir.file("mine/velodyne/000000.bin"));
  ASSERT_GT(scan.size(), 1000u);
  double lowest = 90.0, farthest = 0.0;
  for (const auto& p : scan.xyz) {
    lowest = std::min(lowest, dloam::point_elevation_deg(p));
    farthest = std::max(farthest, p.norm());
  }
  EXPECT_GT(lowest, -15.5);
  EXPECT_LT(farthest, 30.2);
  // KITTI's fitted HDL-64E (its beam table, beam origins 0.12 / 0.20 m above the sensor origin):
  // the run with the same file takes the simulated scans.
  const std::string kitti = std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";
  const CliRun sim = run_dloam("simulate --scenario urban --frames 2 --seed 3 --config " + kitti + " --out " +
                               dir.file("sim"));
  ASSERT_EQ(sim.status, 0) << sim.output;
  const CliRun run = run_dloam("run " + dir.file("sim") + " --out " + dir.file("out") + " --config " + kitti +
                               " --detector none");
  EXPECT_EQ(run.status, 0) << run.output;
  write_text(dir.file("typo.yaml"), "sensor: {N_scna: 64}\n");
  const CliRun typo =
      run_dloam("simulate --frames 1 --config " + dir.file("typo.yaml") + " --out " + dir.file("t"));
  EXPECT_NE(typo.status, 0);
  EXPECT_THAT(typo.output, HasSubstr("typo.yaml"));
  EXPECT_THAT(typo.output, HasSubstr("N_scna"));
}

TEST(RunCli, DropLabelledMovingRunsOnTheStaticPointsOnly) {
  // The perfect detector's reference of the traffic study: the points labels/ marks moving never
  // reach the pipeline (no feature and no map point on them), and the written labels mark them moving.
  const std::string data = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(data)) GTEST_SKIP() << data << " is absent";
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  const std::string config = " --config " + std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";
  const CliRun run = run_dloam("run " + data + " --out " + dir.file("o") + config +
                               " --count 4 --detector geometric --drop-labelled-moving");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("moving points sent to the map: 0.000 %"));
  EXPECT_THAT(run.output, HasSubstr("effective features (Table III): 100.00 %"));
  std::size_t moving = 0;
  for (int i = 0; i < 4; ++i) {
    const auto scan = read_kitti_bin(data + "/velodyne/" + scan_name(i) + ".bin");
    const auto gt = read_labels(data + "/labels/" + scan_name(i) + ".label", scan.size());
    const auto out = read_labels(dir.file("o/labels/" + scan_name(i) + ".label"), scan.size());
    for (std::size_t k = 0; k < gt.size(); ++k) {
      if (!semantic::is_moving(gt[k])) continue;
      ++moving;
      EXPECT_TRUE(semantic::is_moving(out[k])) << "scan " << i << " point " << k;
    }
  }
  EXPECT_GT(moving, 1000u);
  // Without labels there is nothing to delete: an error naming the folder and the option.
  ASSERT_EQ(run_dloam("simulate --frames 2 --out " + dir.file("sim")).status, 0);
  std::filesystem::remove_all(dir.file("sim/labels"));
  const CliRun bare =
      run_dloam("run " + dir.file("sim") + " --out " + dir.file("b") + " --drop-labelled-moving");
  EXPECT_NE(bare.status, 0);
  EXPECT_THAT(bare.output, HasSubstr("--drop-labelled-moving needs"));
  EXPECT_THAT(bare.output, HasSubstr("sim"));
}
