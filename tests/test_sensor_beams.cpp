// Beam tables in the sensor model: validation, rows from the table and from each beam's origin
// height (SensorConfig::row_of_point, BeamLookup, project), and their YAML errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"

using namespace dloam;
using ::testing::HasSubstr;

namespace {
/// Four beams, unevenly spaced, two blocks with different origin heights.
SensorConfig four_beams() {
  SensorConfig s;
  s.preset = "test";
  s.N_scan = 4;
  s.Horizon_SCAN = 360;
  s.beam_elevations_deg = {-20.0, -12.0, -4.0, 0.5};
  s.beam_vertical_offsets_m = {0.1, 0.1, 0.2, 0.2};
  s.min_range = 0.5;
  return s;
}

/// Point of beam `row` at horizontal distance h and azimuth az (deg), from the beam's origin.
Vec3 on_beam(const SensorConfig& s, int row, double h, double az_deg) {
  const double a = az_deg * M_PI / 180.0, e = s.beam_elevation_deg(row) * M_PI / 180.0;
  return {h * std::cos(a), h * std::sin(a), s.beam_vertical_offset_m(row) + h * std::tan(e)};
}

std::string validate_error(const SensorConfig& s) {
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SensorBeams, TableIsValidated) {
  EXPECT_EQ(validate_error(four_beams()), "");
  SensorConfig s = four_beams();
  s.beam_elevations_deg = {-20.0, -12.0, -4.0};
  EXPECT_THAT(validate_error(s), HasSubstr("beam_elevations_deg has 3 entries but N_scan is 4"));
  s.beam_elevations_deg = {-20.0, -4.0, -12.0, 0.5};
  EXPECT_THAT(validate_error(s), HasSubstr("strictly increasing"));
  s.beam_elevations_deg = {-20.0, -12.0, -12.0, 0.5};
  EXPECT_THAT(validate_error(s), HasSubstr("strictly increasing"));
  s.beam_elevations_deg = {-20.0, NAN, -4.0, 0.5};
  EXPECT_THAT(validate_error(s), HasSubstr("beam_elevations_deg must lie in (-89, 89)"));
  s = four_beams();
  s.beam_vertical_offsets_m = {0.1, 0.2};
  EXPECT_THAT(validate_error(s), HasSubstr("beam_vertical_offsets_m has 2 entries but N_scan is 4"));
  s.beam_vertical_offsets_m = {0.1, 0.1, 1.5, 0.2};
  EXPECT_THAT(validate_error(s), HasSubstr("beam_vertical_offsets_m must lie in [-1, 1] m"));
  s.beam_vertical_offsets_m = {};  // empty: all beams at the origin
  EXPECT_EQ(validate_error(s), "");
}

TEST(SensorBeams, BadTablesInYamlNameTheKey) {
  auto error = [](const std::string& yaml) {
    try {
      io::config_from_yaml_string(yaml, "my.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(error("sensor: {preset: VLP-16, beam_vertical_offsets_m: [0.1, 0.2]}"),
              HasSubstr("my.yaml: sensor: beam_vertical_offsets_m has 2 entries but N_scan is 16"));
  EXPECT_THAT(error("sensor: {N_scan: 2, beam_elevations_deg: [1.0, -1.0]}"),
              HasSubstr("strictly increasing"));
  EXPECT_THAT(error("sensor: {beam_vertical_offsets_m: [0.1, x]}"), HasSubstr("beam_vertical_offsets_m[1]"));
  EXPECT_THAT(error("sensor: {N_scan: 2, beam_elevations_deg: [-95.0, 1.0]}"),
              HasSubstr("sensor.beam_elevations_deg = -95"));
  const PipelineConfig ok = io::config_from_yaml_string(
      "sensor: {N_scan: 3, beam_elevations_deg: [-9.0, -1.5, 2.0], beam_vertical_offsets_m: [0.1, 0.1, "
      "0.2]}");
  EXPECT_EQ(ok.sensor.beam_vertical_offsets_m, (std::vector<double>{0.1, 0.1, 0.2}));
  // The dump writes the table back, so it loads again to the same values.
  const PipelineConfig back = io::config_from_yaml_string(io::dump_config(ok));
  EXPECT_EQ(back.sensor.beam_vertical_offsets_m, ok.sensor.beam_vertical_offsets_m);
  EXPECT_EQ(back.sensor.beam_elevations_deg, ok.sensor.beam_elevations_deg);
}

TEST(SensorBeams, RowsFromTheTableAndTheBeamOrigins) {
  const SensorConfig s = four_beams();
  for (int row = 0; row < 4; ++row)
    for (double h : {1.0, 3.0, 10.0, 80.0})
      for (double az : {-170.0, 0.0, 95.0})
        EXPECT_EQ(s.row_of_point(on_beam(s, row, h, az)), row) << row << " " << h;
  // Seen from the sensor origin, beam 0 at 1 m is 5.6 deg higher: without the origin heights
  // it would be taken for beam 1.
  SensorConfig no_offsets = s;
  no_offsets.beam_vertical_offsets_m.clear();
  EXPECT_EQ(no_offsets.row_of_point(on_beam(s, 0, 1.0, 0.0)), 1);
  EXPECT_EQ(no_offsets.row_of_point(on_beam(s, 0, 80.0, 0.0)), 0);
  // Nearest beam in between: -16.2 deg is nearer to -12 than to -20 (bands meet at -16).
  const auto at = [&](double el, double h, double dz) {
    return Vec3(h, 0.0, dz + h * std::tan(el * M_PI / 180.0));
  };
  EXPECT_EQ(s.row_of_point(at(-15.8, 20.0, 0.1)), 1);
  EXPECT_EQ(s.row_of_point(at(-16.2, 20.0, 0.1)), 0);
  // Field of view: half the outer spacing beyond the outer beams (0.5 + 2.25 deg on top).
  EXPECT_EQ(s.row_of_point(at(2.5, 20.0, 0.2)), 3);
  EXPECT_EQ(s.row_of_point(at(3.0, 20.0, 0.2)), -1);
  EXPECT_EQ(s.row_of_point(at(-23.5, 20.0, 0.1)), 0);
  EXPECT_EQ(s.row_of_point(at(-24.5, 20.0, 0.1)), -1);
  EXPECT_EQ(s.row_of_point(Vec3(0.0, 0.0, 5.0)), -1);  // straight up: no elevation band
  // The bracketing neighbour is on the side of the beam the point lies.
  const BeamLookup lookup(s);
  int row = -1, neighbour = -1;
  ASSERT_TRUE(lookup.locate(at(-11.0, 20.0, 0.1), row, neighbour));
  EXPECT_EQ(row, 1);
  EXPECT_EQ(neighbour, 2);
  ASSERT_TRUE(lookup.locate(at(-13.0, 20.0, 0.1), row, neighbour));
  EXPECT_EQ(neighbour, 0);
}

TEST(SensorBeams, ProjectionUsesTheTable) {
  const SensorConfig s = four_beams();
  std::vector<Vec3> points;
  for (int row = 0; row < 4; ++row) points.push_back(on_beam(s, row, 2.0 + 7.0 * row, 10.0 * row));
  const RangeImage img = project(points, s);
  for (int row = 0; row < 4; ++row) {
    EXPECT_EQ(img.row_of_point[static_cast<std::size_t>(row)], row);
    EXPECT_EQ(img.point_at(row, img.col_of_point[static_cast<std::size_t>(row)]), row);
  }
}

TEST(SensorBeams, PresetRowsMatchTheElevationSearch) {
  // Without origin heights, row_of_point is row_of_elevation of the point's elevation.
  for (const auto& name : sensor_preset_names()) {
    const SensorConfig s = sensor_preset(name);
    if (!s.beam_vertical_offsets_m.empty()) continue;  // Ouster presets: beam origins off the axis
    for (double el = s.beam_elevation_deg(0) - 3.0; el < s.beam_elevation_deg(s.N_scan - 1) + 3.0;
         el += 0.037) {
      const Vec3 p(12.0, -3.0, std::hypot(12.0, 3.0) * std::tan(el * M_PI / 180.0));
      EXPECT_EQ(s.row_of_point(p), s.row_of_elevation(point_elevation_deg(p))) << name << " " << el;
    }
  }
}
