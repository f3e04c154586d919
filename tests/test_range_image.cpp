#include <gtest/gtest.h>

#include <cmath>

#include "dloam/core/range_image.hpp"

using namespace dloam;

namespace {
Vec3 dir(double az_deg, double el_deg, double r) {
  const double a = az_deg * M_PI / 180.0, e = el_deg * M_PI / 180.0;
  return {r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a), r * std::sin(e)};
}
}  // namespace

TEST(Sensor, PresetsValidateAndHaveTheirBeamCounts) {
  const std::pair<const char*, int> expected[] = {
      {"HDL-64E", 64}, {"HDL-32E", 32}, {"VLP-16", 16}, {"OS1-64", 64}, {"OS1-128", 128}};
  for (const auto& [name, rows] : expected) {
    const auto s = sensor_preset(name);
    EXPECT_NO_THROW(s.validate()) << name;
    EXPECT_EQ(s.N_scan, rows) << name;
    EXPECT_NEAR(s.beam_elevation_deg(0), s.Pit_bottom, 1e-9) << name;
    EXPECT_NEAR(s.beam_elevation_deg(rows - 1), s.fov_top, 1e-9) << name;
  }
  EXPECT_THROW(sensor_preset("HDL-65"), std::invalid_argument);
}

TEST(Sensor, NearestBeamRowAndOutsideFov) {
  const auto s = sensor_preset("VLP-16");  // -15..15 every 2 deg
  EXPECT_EQ(s.row_of_elevation(-15.0), 0);
  EXPECT_EQ(s.row_of_elevation(-13.2), 1);
  EXPECT_EQ(s.row_of_elevation(15.0), 15);
  EXPECT_EQ(s.row_of_elevation(17.0), -1);
  EXPECT_EQ(s.row_of_elevation(-16.5), -1);
  const auto h = sensor_preset("HDL-64E");
  EXPECT_EQ(h.row_of_elevation(-24.9), 0);
  EXPECT_EQ(h.row_of_elevation(2.0), 63);
  EXPECT_EQ(h.row_of_elevation(-8.5), 32);  // -8.5 is 0.17 from the upper block's -8.33, 0.33 from -8.83
  EXPECT_EQ(h.row_of_elevation(-8.7), 31);
}

TEST(RangeImage, ColumnsFollowTheSweepFromTheRearClockwise) {
  const int cols = 360;
  EXPECT_EQ(azimuth_column(-1.0, 1e-9, cols), 0);     // rear, just clockwise of it (towards +y)
  EXPECT_EQ(azimuth_column(-1.0, -1e-9, cols), 359);  // rear, just before the sweep ends
  EXPECT_EQ(azimuth_column(0.0, 1.0, cols), 90);      // left (+y) comes a quarter turn later
  EXPECT_EQ(azimuth_column(1.0, 0.0, cols), 180);     // front at mid-sweep
  EXPECT_EQ(azimuth_column(0.0, -1.0, cols), 270);    // right
  EXPECT_NEAR(azimuth_time(1.0, 0.0), 0.5, 1e-12);
}

TEST(RangeImage, KeepsNearestPointPerPixelAndMapsBothWays) {
  SensorConfig s = sensor_preset("VLP-16");
  s.Horizon_SCAN = 360;
  std::vector<Vec3> pts = {dir(10.2, 1.0, 10.0), dir(10.3, 1.1, 5.0), dir(-40.0, -15.0, 20.0),
                           dir(0.0, 30.0, 10.0), dir(5.0, 0.0, 0.5),  dir(5.0, 0.0, 500.0)};
  const RangeImage img = project(pts, s);
  ASSERT_EQ(img.rows, 16);
  // Points 0 and 1 share a pixel; the nearer (1) wins, both keep their row/col.
  EXPECT_EQ(img.pixel_of_point(0), img.pixel_of_point(1));
  EXPECT_EQ(img.point_of_pixel[static_cast<std::size_t>(img.pixel_of_point(0))], 1);
  EXPECT_FLOAT_EQ(img.range[static_cast<std::size_t>(img.pixel_of_point(0))], 5.0f);
  EXPECT_EQ(img.row_of_point[2], 0);
  EXPECT_EQ(img.point_of_pixel[static_cast<std::size_t>(img.pixel_of_point(2))], 2);
  // Outside vertical FOV, too near, too far: no pixel.
  EXPECT_EQ(img.pixel_of_point(3), -1);
  EXPECT_EQ(img.pixel_of_point(4), -1);
  EXPECT_EQ(img.pixel_of_point(5), -1);
  int filled = 0;
  for (int p : img.point_of_pixel) filled += p >= 0;
  EXPECT_EQ(filled, 2);
}

TEST(RangeImage, ReprojectedRangesFollowTheNewAzimuthKeepTheRowAndDropExcludedPixels) {
  SensorConfig s = sensor_preset("VLP-16");
  s.Horizon_SCAN = 360;
  // Two points in one pixel (the nearer wins), one alone, one outside the field of view.
  const std::vector<Vec3> before = {dir(10.2, 1.0, 10.0), dir(10.3, 1.1, 5.0), dir(-40.0, -15.0, 20.0),
                                    dir(0.0, 30.0, 10.0)};
  const RangeImage img = project(before, s);
  // A second de-skew turns every point by 3 deg and moves the first two apart in range.
  const double turn = 3.0;
  const std::vector<Vec3> after = {dir(10.2 + turn, 1.0, 4.0), dir(10.3 + turn, 1.1, 6.0),
                                   dir(-40.0 + turn, -15.0, 21.0), dir(turn, 30.0, 10.0)};
  const std::vector<float> range = reprojected_range(img, after, {});
  ASSERT_EQ(range.size(), img.range.size());
  const auto at = [&](std::size_t i) {
    const Vec3& p = after[i];
    return range[static_cast<std::size_t>(
        img.pixel(img.row_of_point[i], azimuth_column(p.x(), p.y(), img.cols)))];
  };
  EXPECT_FLOAT_EQ(at(0), 4.0f);  // now the nearer of the two
  EXPECT_FLOAT_EQ(at(2), 21.0f);
  // The old pixels are empty: every point moved by three columns.
  EXPECT_EQ(range[static_cast<std::size_t>(img.pixel_of_point(0))], 0.0f);
  EXPECT_EQ(range[static_cast<std::size_t>(img.pixel_of_point(2))], 0.0f);
  int filled = 0;
  for (float r : range) filled += r > 0.0f;
  EXPECT_EQ(filled, 2);  // the point outside the field of view stays out
  // The rows are the image's, not recomputed from the new elevation.
  std::vector<Vec3> lifted = after;
  lifted[2] = dir(-40.0 + turn, -13.0, 21.0);  // the next beam's elevation
  const std::vector<float> kept_row = reprojected_range(img, lifted, {});
  EXPECT_FLOAT_EQ(
      kept_row[static_cast<std::size_t>(img.pixel(0, azimuth_column(lifted[2].x(), lifted[2].y(), 360)))],
      21.0f);
  // A point whose pixel in the image is excluded (a moving object) stays out.
  std::vector<std::uint8_t> excluded(img.range.size(), 0);
  excluded[static_cast<std::size_t>(img.pixel_of_point(0))] = 1;
  const std::vector<float> masked = reprojected_range(img, after, excluded);
  filled = 0;
  for (float r : masked) filled += r > 0.0f;
  EXPECT_EQ(filled, 1);
}
