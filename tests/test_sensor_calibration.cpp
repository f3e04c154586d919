// Fitting the beam table from ring-by-ring scans (beam_calibration.hpp): a synthetic sensor with
// known beams is recovered; on kitti-raw-0005 the shipped config/kitti-raw.yaml table puts every
// point on its own beam's row, and `dloam calibrate-beams` reproduces that table.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "cli_util.hpp"
#include "dloam/core/beam_calibration.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"

using namespace dloam;
using ::testing::HasSubstr;

namespace {
/// 16 beams, two blocks at different origin heights, uneven spacing.
SensorConfig true_sensor() {
  SensorConfig s = sensor_preset("VLP-16");
  s.beam_elevations_deg.clear();
  for (int k = 0; k < 16; ++k) {
    s.beam_elevations_deg.push_back(-15.0 + 2.0 * k + 0.3 * std::sin(k));
    s.beam_vertical_offsets_m.push_back(k < 8 ? 0.12 : 0.2);
  }
  return s;
}

/// A scan stored ring by ring, top beam first, each ring one counter-clockwise turn starting
/// near azimuth 0 (as KITTI), with azimuth jitter and random ranges (walls and ground).
std::vector<Vec3> ring_ordered_scan(const SensorConfig& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.03, 0.03), dist(3.0, 40.0);
  std::vector<Vec3> points;
  for (int row = s.N_scan - 1; row >= 0; --row) {
    const double t = std::tan(s.beam_elevation_deg(row) * M_PI / 180.0);
    for (int i = 0; i < 900; ++i) {
      const double az = (0.05 + 0.4 * i + jitter(rng)) * M_PI / 180.0;
      double h = dist(rng);
      if (t < 0.0) h = std::min(h, 1.7 / -t);  // ground 1.7 m below
      const double a = az > M_PI ? az - 2.0 * M_PI : az;
      points.emplace_back(h * std::cos(a), h * std::sin(a), s.beam_vertical_offset_m(row) + h * t);
    }
  }
  return points;
}
}  // namespace

TEST(BeamCalibration, RingsFromThePointOrder) {
  std::mt19937 rng(3);
  const SensorConfig s = true_sensor();
  const std::vector<Vec3> points = ring_ordered_scan(s, rng);
  const std::vector<int> ring = rings_from_point_order(points);
  for (std::size_t i = 0; i < points.size(); ++i) ASSERT_EQ(ring[i], static_cast<int>(i / 900)) << i;
}

TEST(BeamCalibration, RecoversKnownBeams) {
  std::mt19937 rng(5);
  const SensorConfig truth = true_sensor();
  SensorConfig start = sensor_preset("VLP-16");  // nominal table, no origin heights
  BeamTableFit fit(start);
  for (int scan = 0; scan < 3; ++scan) fit.add(ring_ordered_scan(truth, rng), "scan");
  const SensorConfig fitted = fit.fitted_sensor();
  ASSERT_EQ(fitted.beam_elevations_deg.size(), 16u);
  for (int k = 0; k < 16; ++k) {
    EXPECT_NEAR(fitted.beam_elevation_deg(k), truth.beam_elevation_deg(k), 0.002) << k;
    EXPECT_NEAR(fitted.beam_vertical_offset_m(k), truth.beam_vertical_offset_m(k), 0.002) << k;
  }
  EXPECT_EQ(fit.fit().front().ring, 15);  // stored top beam first
}

TEST(BeamCalibration, RejectsScansNotStoredRingByRing) {
  std::mt19937 rng(7);
  std::vector<Vec3> points = ring_ordered_scan(true_sensor(), rng);
  std::shuffle(points.begin(), points.end(), rng);
  BeamTableFit fit(sensor_preset("VLP-16"));
  try {
    fit.add(points, "shuffled.bin");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("shuffled.bin"));
    EXPECT_THAT(e.what(), HasSubstr("the sensor has 16 beams"));
  }
  points.resize(5 * 900);  // 5 of 16 rings
  EXPECT_THROW(BeamTableFit(sensor_preset("VLP-16")).add(points, "short.bin"), InputError);
}

TEST(BeamCalibration, KittiTablePutsPointsOnTheirBeamRows) {
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir + "/velodyne")) GTEST_SKIP() << "no " << dir;
  const SensorConfig fitted =
      io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml").sensor;
  const SensorConfig preset = sensor_preset("HDL-64E");
  ASSERT_EQ(fitted.beam_vertical_offsets_m.size(), 64u);
  std::size_t in_range = 0, lost_fitted = 0, lost_preset = 0, outside_fitted = 0, off_ring = 0;
  std::vector<std::size_t> row_points(64, 0);
  for (int scan : {0, 50, 99}) {
    char name[32];
    std::snprintf(name, sizeof(name), "/velodyne/%06d.bin", scan);
    std::vector<Vec3> points = io::read_kitti_bin(dir + name).xyz;
    correct_vertical_angle(points, fitted.vertical_angle_correction_deg);
    const std::vector<int> ring = rings_from_point_order(points);
    const RangeImage a = project(points, fitted), b = project(points, preset);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double r = points[i].norm();
      if (!(r >= fitted.min_range && r <= fitted.max_range)) continue;
      ++in_range;
      const int px = a.pixel_of_point(i);
      outside_fitted += px < 0;
      if (px < 0) continue;
      ++row_points[static_cast<std::size_t>(a.row_of_point[i])];
      lost_fitted += a.point_of_pixel[static_cast<std::size_t>(px)] != static_cast<int>(i);
      off_ring += ring[i] < 64 && a.row_of_point[i] != 63 - ring[i];  // KITTI stores the top beam first
      const int pb = b.pixel_of_point(i);
      lost_preset += pb < 0 || b.point_of_pixel[static_cast<std::size_t>(pb)] != static_cast<int>(i);
    }
  }
  const double n = static_cast<double>(in_range);
  EXPECT_LT(outside_fitted / n, 0.001);
  EXPECT_LT(off_ring / n, 0.002);    // the ring's own row (a few points at the turn of a ring)
  EXPECT_LT(lost_fitted / n, 0.08);  // two firings in one of 2048 columns
  EXPECT_GT(lost_preset / n, 0.12);  // the nominal table: rows shifted, top beams outside
  for (int row = 0; row < 64; ++row) EXPECT_GT(row_points[static_cast<std::size_t>(row)], 3u * 1000u) << row;
}

TEST(BeamCalibration, SpeedMatrixProjectsWithTheBeamOrigins) {
  // A scan compared with itself (identity motion) is static everywhere, also near the car where
  // the beam origin heights move a point up to 3 rows from where its elevation alone puts it.
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir + "/velodyne")) GTEST_SKIP() << "no " << dir;
  const SensorConfig s = io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml").sensor;
  std::vector<Vec3> points = io::read_kitti_bin(dir + "/velodyne/000010.bin").xyz;
  correct_vertical_angle(points, s.vertical_angle_correction_deg);
  const RangeImage img = project(points, s);
  const SpeedMatrix m = compute_speed_matrix(img, points, Pose::Identity(), img.range, s);
  std::size_t known = 0, moving = 0, near = 0, near_moving = 0;
  for (std::size_t px = 0; px < m.speed.size(); ++px) {
    if (!m.known(static_cast<int>(px))) continue;
    ++known;
    moving += m.speed[px] > 0.1f;
    if (img.range[px] < 8.0f) {
      ++near;
      near_moving += m.speed[px] > 0.1f;
    }
  }
  ASSERT_GT(near, 10000u);
  EXPECT_GT(known, 0.95 * 64 * 2048 * 0.85);
  EXPECT_LT(static_cast<double>(moving) / known, 0.01);
  EXPECT_LT(static_cast<double>(near_moving) / near, 0.01);
}

TEST(BeamCalibration, CliReproducesTheShippedTable) {
  const std::string dir = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(dir + "/velodyne")) GTEST_SKIP() << "no " << dir;
  const std::string config = std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";
  const std::string out = (std::filesystem::temp_directory_path() / "dloam_test_beams.yaml").string();
  const auto run =
      test::run_dloam("calibrate-beams " + dir + " --config " + config + " --every 25 --out " + out);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("fitted   outside FOV  0.00 %"));
  const SensorConfig shipped = io::load_config(config).sensor;
  const SensorConfig refit = io::load_config(out).sensor;
  ASSERT_EQ(refit.beam_elevations_deg.size(), 64u);
  for (int k = 0; k < 64; ++k) {
    EXPECT_NEAR(refit.beam_elevation_deg(k), shipped.beam_elevation_deg(k), 0.01) << k;
    EXPECT_NEAR(refit.beam_vertical_offset_m(k), shipped.beam_vertical_offset_m(k), 0.005) << k;
  }
  std::filesystem::remove(out);
  EXPECT_NE(test::run_dloam("calibrate-beams " + dir + " --preset VLP-16").status, 0);  // 64 rings, 16 beams
}
