// The sensor model from the data (core/sensor_estimation.hpp, `dloam check --write-sensor`, the
// preset auto): simulated sensors of 16 to 128 beams (uneven spacing, 90-105 deg fields, beams
// 0.1 deg apart, two origin heights, interleaved laser blocks, few far points) are recovered from
// their scans, and so are the beams of real decoded scans (the shared sensor data) and the fitted
// table of the KITTI drive, all without rings; degenerate input gives an error, not a model; and
// the presets table.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "cli_util.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/sensor_estimation.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "sim_test_util.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using dloam::test::CliRun;
using dloam::test::run_dloam;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;

namespace {

/// How an estimate matches a true table.
struct Recovery {
  int expected = 0;                                  ///< true beams with enough points in the scans
  int found = 0;                                     ///< of those, estimated within a tenth of their spacing
  int extra = 0;                                     ///< estimated beams near no true beam
  double elevation_error = 0.0, offset_error = 0.0;  ///< largest, over the beams found
};

std::ostream& operator<<(std::ostream& o, const Recovery& r) {
  return o << r.found << " of " << r.expected << " beams found, " << r.extra << " extra, elevation error "
           << r.elevation_error << " deg, origin height error " << r.offset_error << " m";
}

/// Every true beam with at least `min_points` points must have an estimated beam within a tenth
/// of its distance to the nearest other beam; every estimated beam must be such a match.
Recovery compare(const SensorConfig& truth, const std::vector<std::size_t>& points_per_beam,
                 const SensorConfig& est, std::size_t min_points) {
  Recovery r;
  auto tolerance = [&](int k) {
    double gap = INFINITY;
    if (k > 0) gap = std::min(gap, truth.beam_elevation_deg(k) - truth.beam_elevation_deg(k - 1));
    if (k + 1 < truth.N_scan)
      gap = std::min(gap, truth.beam_elevation_deg(k + 1) - truth.beam_elevation_deg(k));
    return 0.1 * gap;
  };
  for (int k = 0; k < truth.N_scan; ++k) {
    if (points_per_beam[static_cast<std::size_t>(k)] < min_points) continue;
    ++r.expected;
    int best = -1;
    double err = INFINITY;
    for (int j = 0; j < est.N_scan; ++j) {
      const double e = std::abs(est.beam_elevation_deg(j) - truth.beam_elevation_deg(k));
      if (e < err) {
        err = e;
        best = j;
      }
    }
    if (err > tolerance(k)) continue;
    ++r.found;
    r.elevation_error = std::max(r.elevation_error, err);
    r.offset_error = std::max(r.offset_error,
                              std::abs(est.beam_vertical_offset_m(best) - truth.beam_vertical_offset_m(k)));
  }
  for (int j = 0; j < est.N_scan; ++j) {
    bool near = false;
    for (int k = 0; k < truth.N_scan && !near; ++k)
      near = std::abs(est.beam_elevation_deg(j) - truth.beam_elevation_deg(k)) <= tolerance(k);
    r.extra += !near;
  }
  return r;
}

/// Three scans (frames 0, 10, 20) of a simulated urban drive seen by `sensor`, and the points of
/// each beam in them.
std::vector<std::vector<Vec3>> simulated_scans(const SensorConfig& sensor, std::vector<std::size_t>& per_beam,
                                               std::uint64_t seed = 2) {
  sim::Simulator simulator = test::make_simulator(sim::ScenarioKind::Urban, 30, seed, sensor);
  std::vector<std::vector<Vec3>> scans;
  per_beam.assign(static_cast<std::size_t>(sensor.N_scan), 0);
  for (const int frame : {0, 10, 20}) {
    const sim::SimFrame f = simulator.frame(frame);
    scans.push_back(f.scan.cloud.xyz);
    for (const auto row : f.scan.rows) ++per_beam[row];
  }
  return scans;
}

/// 64 beams over 90 deg, dense near the horizon (0.12 deg) and 2.3 deg apart at the edges, in two
/// blocks 0.05 m and 0.13 m above the sensor origin: a wide-angle sensor without a preset.
SensorConfig wide_sensor() {
  SensorConfig s;
  s.preset = "custom";
  s.N_scan = 64;
  s.Horizon_SCAN = 1024;
  for (int k = 0; k < 64; ++k) {
    const double x = -1.0 + 2.0 * k / 63.0;
    s.beam_elevations_deg.push_back(std::round((x < 0 ? -45.0 : 45.0) * std::pow(std::abs(x), 1.6) * 1000.0) /
                                    1000.0);
    s.beam_vertical_offsets_m.push_back(k < 32 ? 0.05 : 0.13);
  }
  s.Pit_bottom = s.beam_elevations_deg.front();
  s.fov_top = s.beam_elevations_deg.back();
  s.min_range = 0.5;
  s.max_range = 100.0;
  return s;
}

/// An HDL-64E whose laser blocks interleave: 0.42 deg apart, origins at 0.12 m (below -11 deg),
/// alternating 0.12 / 0.19 m up to -8 deg, 0.19 m above; seen from the sensor origin, the beams of
/// the two blocks cross at about 9 m.
SensorConfig interleaved_sensor() {
  SensorConfig s = sensor_preset("HDL-64E");
  s.preset = "custom";
  s.beam_elevations_deg.clear();
  for (int k = 0; k < 64; ++k) {
    const double e = -24.9 + 0.42 * k;
    s.beam_elevations_deg.push_back(e);
    s.beam_vertical_offsets_m.push_back(e < -11.0 ? 0.12 : e < -8.0 ? (k % 2 ? 0.19 : 0.12) : 0.19);
  }
  s.Pit_bottom = s.beam_elevations_deg.front();
  s.fov_top = s.beam_elevations_deg.back();
  return s;
}

SensorConfig kitti_table() {
  SensorConfig s = io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml").sensor;
  s.vertical_angle_correction_deg = 0.0;  // simulated: the table is the truth
  return s;
}

/// One ideal sweep of `s`: every beam at 1800 azimuths, from its own origin, 5-60 m away.
std::vector<Vec3> ideal_sweep(const SensorConfig& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> distance(5.0, 60.0);
  std::vector<Vec3> points;
  for (int row = 0; row < s.N_scan; ++row)
    for (int k = 0; k < 1800; ++k) {
      const double az = 2.0 * M_PI * k / 1800.0, h = distance(rng);
      points.emplace_back(
          h * std::cos(az), h * std::sin(az),
          s.beam_vertical_offset_m(row) + h * std::tan(s.beam_elevation_deg(row) * M_PI / 180.0));
    }
  return points;
}

std::string error_of(const std::vector<std::vector<Vec3>>& scans) {
  return test::input_error_of([&] { (void)estimate_sensor_model(scans, {}); });
}

}  // namespace

TEST(SensorEstimate, SimulatedSensorsAreRecovered) {
  struct Case {
    std::string name;
    SensorConfig sensor;
  };
  SensorConfig short_range = wide_sensor();
  short_range.max_range = 20.0;  // few far points: nothing beyond 20 m
  const std::vector<Case> cases = {
      {"VLP-16 (16 beams, 2 deg)", sensor_preset("VLP-16")},
      {"VLP-32C (32 beams, 0.33 .. 9.4 deg apart)", sensor_preset("VLP-32C")},
      {"KITTI's HDL-64E (two blocks at 0.12 / 0.20 m)", kitti_table()},
      {"interleaved HDL-64E blocks", interleaved_sensor()},
      {"VLS-128 (128 beams, 0.11 deg apart)", sensor_preset("VLS-128")},
      {"OS0-128 (92 deg, Ouster beam origins)", sensor_preset("OS0-128")},
      {"PandarQT64 (104 deg)", sensor_preset("PandarQT64")},
      {"wide 64-beam sensor, no preset", wide_sensor()},
      {"wide 64-beam sensor seeing 20 m", short_range},
  };
  for (const Case& c : cases) {
    std::vector<std::size_t> per_beam;
    const auto scans = simulated_scans(c.sensor, per_beam);
    const SensorModelEstimate est = estimate_sensor_model(scans, {0.0, 0.1, 0.2});
    const Recovery r = compare(c.sensor, per_beam, est.sensor, 100);
    EXPECT_GE(r.expected, c.sensor.N_scan * 3 / 4) << c.name << ": the simulation should see most beams";
    EXPECT_EQ(r.found, r.expected) << c.name << ": " << r;
    EXPECT_EQ(r.extra, 0) << c.name << ": " << r;
    EXPECT_LT(r.offset_error, 0.01) << c.name << ": " << r;
    EXPECT_EQ(est.sensor.Horizon_SCAN, c.sensor.Horizon_SCAN) << c.name;
    EXPECT_GT(est.on_beam_fraction, 0.95) << c.name;
    EXPECT_TRUE(est.scan_rate_measured) << c.name;
    EXPECT_DOUBLE_EQ(est.sensor.scan_rate_hz, 10.0) << c.name;
    EXPECT_LE(est.sensor.max_range, 1.1 * c.sensor.max_range) << c.name;
    EXPECT_GE(est.sensor.max_range, 0.5 * c.sensor.max_range) << c.name;
    EXPECT_EQ(est.sensor.preset, "custom");
    EXPECT_NO_THROW(est.sensor.validate()) << c.name;
  }
}

TEST(SensorEstimate, EveryPresetIsRecoveredFromIdealSweeps) {
  std::mt19937 rng(7);
  for (const auto& name : sensor_preset_names()) {
    const SensorConfig s = sensor_preset(name);
    const SensorModelEstimate est = estimate_sensor_model({ideal_sweep(s, rng), ideal_sweep(s, rng)}, {});
    const Recovery r =
        compare(s, std::vector<std::size_t>(static_cast<std::size_t>(s.N_scan), 3600), est.sensor, 1);
    EXPECT_EQ(r.found, s.N_scan) << name << ": " << r;
    EXPECT_EQ(r.extra, 0) << name << ": " << r;
    EXPECT_LT(r.offset_error, 0.002) << name << ": " << r;
    const PresetMatch m = match_preset(est.sensor, name);
    EXPECT_TRUE(m.resembles) << name << " " << m.distance_deg;
    EXPECT_EQ(est.sensor.Horizon_SCAN, 1800) << name;
  }
}

TEST(SensorEstimate, ThePresetOfAPresetsScansIsFound) {
  for (const char* name : {"VLP-32C", "VLS-128", "OS2-128", "Pandar64"}) {
    std::vector<std::size_t> per_beam;
    const SensorConfig truth = sensor_preset(name);
    const SensorModelEstimate est = estimate_sensor_model(simulated_scans(truth, per_beam, 5), {});
    const PresetMatch m = nearest_preset(est.sensor);
    EXPECT_EQ(m.preset, truth.preset);
    EXPECT_TRUE(m.resembles || est.sensor.N_scan != truth.N_scan) << name << " " << m.distance_deg;
    EXPECT_LT(m.distance_deg, 0.01) << name;
    EXPECT_FALSE(est.scan_rate_measured);  // no stamps: assumed
    EXPECT_THAT(est.notes, ::testing::Contains(HasSubstr("10 Hz assumed")));
  }
}

TEST(SensorEstimate, RealDecodedScansGiveTheirBeams) {
  // One scan each, decoded by nebula from real sensors (mostly indoors: few far points), and the
  // presets made from the calibration tables of the same data set.
  const std::string dir = DLOAM_SENSORS_DIR;
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no " << dir;
  const std::pair<const char*, const char*> cases[] = {
      {"velodyne/nebula/vlp16/1673400472138016708.pcd", "VLP-16"},
      {"velodyne/nebula/vlp32/1713492677464078412.pcd", "VLP-32C"},
      {"velodyne/nebula/vls128/1585897255376374245.pcd", "VLS-128"},
      {"hesai/nebula/40p/1673400149711850138.pcd", "Pandar40P"},
      {"hesai/nebula/64/1673403880898440686.pcd", "Pandar64"},
      {"hesai/nebula/qt64/1673401196087570870.pcd", "PandarQT64"},
      {"hesai/nebula/qt128/1730273789174759609.pcd", "PandarQT128"},
      {"hesai/nebula/xt32/1673400678101968885.pcd", "PandarXT32"},
  };
  for (const auto& [file, preset] : cases) {
    const PointCloud cloud = io::read_scan_file(dir + "/" + file);
    const SensorConfig truth = sensor_preset(preset);
    // Points per beam: these decoders put every point exactly on its table's cone.
    std::vector<std::size_t> per_beam(static_cast<std::size_t>(truth.N_scan), 0);
    for (const Vec3& p : cloud.xyz) {
      if (std::hypot(p.x(), p.y()) < 0.1) continue;
      int best = 0;
      for (int k = 1; k < truth.N_scan; ++k)
        if (std::abs(point_elevation_deg(p) - truth.beam_elevation_deg(k)) <
            std::abs(point_elevation_deg(p) - truth.beam_elevation_deg(best)))
          best = k;
      ++per_beam[static_cast<std::size_t>(best)];
    }
    const SensorModelEstimate est = estimate_sensor_model({cloud.xyz}, {});
    const Recovery r = compare(truth, per_beam, est.sensor, 100);
    EXPECT_EQ(r.found, r.expected) << preset << ": " << r;
    EXPECT_EQ(r.extra, 0) << preset << ": " << r;
    EXPECT_LT(r.elevation_error, 0.002) << preset << ": " << r;
    ASSERT_GT(est.azimuth_step_deg, 0.0) << preset;
    const double firings = 360.0 / est.azimuth_step_deg;
    EXPECT_NEAR(firings, truth.Horizon_SCAN, 0.01 * truth.Horizon_SCAN) << preset;
    EXPECT_GE(est.sensor.Horizon_SCAN, 0.97 * firings) << preset;
    EXPECT_LE(est.sensor.Horizon_SCAN, 1.03 * firings) << preset;
  }
}

TEST(SensorEstimate, DegenerateInputIsAnErrorNotAModel) {
  // One scan of 10 points.
  std::vector<Vec3> ten;
  for (int i = 0; i < 10; ++i) ten.emplace_back(5.0 + i, 1.0, -1.0);
  EXPECT_THAT(error_of({ten}), HasSubstr("only 10 of the 10 points in 1 scan"));
  EXPECT_THAT(error_of({}), HasSubstr("only 0"));
  // All points in one plane: a flat ground of 40 x 40 m seen from 1.7 m.
  std::vector<Vec3> plane;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) plane.emplace_back(-20.0 + 0.2 * i, -20.0 + 0.2 * j, -1.7);
  EXPECT_THAT(error_of({plane}), HasSubstr("lie within 0.0 cm (rms) of one plane"));
  // Points spread evenly through a volume: no beams.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-30.0, 30.0), z(-3.0, 10.0);
  std::vector<Vec3> cloud;
  for (int i = 0; i < 50000; ++i) cloud.emplace_back(xy(rng), xy(rng), z(rng));
  EXPECT_THAT(error_of({cloud}), HasSubstr("no distinct beams"));
  // A sensor tilted by 3 deg (points not in its own frame): the beams blur.
  std::vector<std::size_t> per_beam;
  auto scans = simulated_scans(sensor_preset("VLP-32C"), per_beam);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(3.0 * M_PI / 180.0, Vec3::UnitX()).toRotationMatrix();
  for (auto& scan : scans)
    for (auto& p : scan) p = tilt * p;
  EXPECT_THAT(error_of(scans), HasSubstr("sensor frame"));
}

TEST(SensorEstimate, VerticalCorrectionIsAppliedAndKept) {
  // KITTI's scans need +0.22 deg: a sensor simulated with it is recovered as its table when the
  // estimate applies the same correction.
  SensorConfig truth = sensor_preset("VLP-32C");
  truth.vertical_angle_correction_deg = 0.22;
  std::vector<std::size_t> per_beam;
  const auto scans = simulated_scans(truth, per_beam);
  SensorEstimationConfig config;
  config.vertical_angle_correction_deg = 0.22;
  const SensorModelEstimate est = estimate_sensor_model(scans, {}, config);
  EXPECT_EQ(est.sensor.vertical_angle_correction_deg, 0.22);
  const Recovery r = compare(truth, per_beam, est.sensor, 100);
  EXPECT_EQ(r.found, r.expected) << r;
  EXPECT_EQ(r.extra, 0) << r;
  // Without it every beam is 0.22 deg lower.
  const SensorModelEstimate raw = estimate_sensor_model(scans, {});
  EXPECT_NEAR(raw.sensor.beam_elevation_deg(raw.sensor.N_scan - 1), est.sensor.fov_top - 0.22, 0.003);
}

TEST(SensorPresets, OneValidTableEachWithItsSource) {
  const auto info = sensor_preset_info();
  std::set<std::string> names;
  for (const auto& p : info) {
    std::string upper = p.name;
    for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_TRUE(names.insert(upper).second) << "duplicate preset " << p.name;
    EXPECT_FALSE(p.source.empty()) << p.name;
    const SensorConfig s = sensor_preset(p.name);
    EXPECT_NO_THROW(s.validate()) << p.name;
    EXPECT_EQ(s.preset, p.name);
    EXPECT_EQ(s.N_scan, p.beams) << p.name;
  }
  for (const char* required : {"HDL-64E", "HDL-32E", "VLP-16", "VLP-32C", "VLS-128", "OS0-32", "OS0-64",
                               "OS0-128", "OS1-32", "OS1-64", "OS1-128", "OS2-32", "OS2-64", "OS2-128",
                               "PANDAR40P", "PANDAR64", "PANDARQT64", "PANDARQT128", "PANDARXT32"})
    EXPECT_TRUE(names.count(required)) << required;
  // Published tables kept as given: the VLP-32C's nominal angles, the Ouster origin geometry.
  const SensorConfig vlp32 = sensor_preset("vlp-32c");
  EXPECT_EQ(vlp32.beam_elevation_deg(0), -25.0);
  EXPECT_EQ(vlp32.beam_elevation_deg(1), -15.639);
  EXPECT_EQ(vlp32.beam_elevation_deg(31), 15.0);
  const SensorConfig os0 = sensor_preset("OS0-128");
  EXPECT_EQ(os0.beam_elevation_deg(0), -46.26);
  EXPECT_NEAR(os0.beam_vertical_offset_m(0), 0.03618 + 0.02767 * std::tan(46.26 * M_PI / 180.0), 1e-4);
  EXPECT_TRUE(sensor_preset("VLS-128").beam_vertical_offsets_m.empty());
  // The list in the help texts is the table.
  EXPECT_THAT(sensor_preset_list(), HasSubstr("PandarQT128"));
  EXPECT_THAT(test::input_error_of([] { (void)io::default_config("HDL-99"); }), HasSubstr("PandarXT32"));
}

TEST(SensorPresets, TheOriginalFivePresetsAreUnchanged) {
  // The values these presets had before the table (runs with them stay byte-identical).
  const SensorConfig hdl64 = sensor_preset("HDL-64E");
  ASSERT_EQ(hdl64.beam_elevations_deg.size(), 64u);
  EXPECT_EQ(hdl64.beam_elevations_deg[0], -24.9);
  EXPECT_EQ(hdl64.beam_elevations_deg[31], -24.9 + (-8.83 - -24.9) * 31 / 31);
  EXPECT_EQ(hdl64.beam_elevations_deg[32], -8.33);
  EXPECT_EQ(hdl64.beam_elevations_deg[63], -8.33 + (2.0 - -8.33) * 31 / 31);
  EXPECT_EQ(hdl64.Pit_bottom, -24.9);
  EXPECT_EQ(hdl64.fov_top, 2.0);
  EXPECT_EQ(hdl64.Horizon_SCAN, 2048);
  EXPECT_EQ(hdl64.min_range, 2.5);
  EXPECT_EQ(hdl64.max_range, 120.0);
  EXPECT_TRUE(hdl64.beam_vertical_offsets_m.empty());
  struct Uniform {
    const char* name;
    int beams, columns;
    double lo, hi, min_range, max_range;
  };
  for (const Uniform& u : {Uniform{"HDL-32E", 32, 1800, -30.67, 10.67, 1.0, 100.0},
                           Uniform{"VLP-16", 16, 1800, -15.0, 15.0, 1.0, 100.0},
                           Uniform{"OS1-64", 64, 1024, -16.6, 16.6, 1.0, 120.0},
                           Uniform{"OS1-128", 128, 1024, -22.5, 22.5, 1.0, 120.0}}) {
    const SensorConfig s = sensor_preset(u.name);
    EXPECT_TRUE(s.beam_elevations_deg.empty()) << u.name;
    EXPECT_TRUE(s.beam_vertical_offsets_m.empty()) << u.name;
    EXPECT_EQ(s.N_scan, u.beams) << u.name;
    EXPECT_EQ(s.Horizon_SCAN, u.columns) << u.name;
    EXPECT_EQ(s.Pit_bottom, u.lo) << u.name;
    EXPECT_EQ(s.fov_top, u.hi) << u.name;
    EXPECT_EQ(s.min_range, u.min_range) << u.name;
    EXPECT_EQ(s.max_range, u.max_range) << u.name;
    EXPECT_EQ(s.scan_rate_hz, 10.0) << u.name;
  }
}

TEST(SensorEstimateCli, WriteSensorRecoversAWideSensorAndRunsOnIt) {
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  const SensorConfig truth = wide_sensor();
  PipelineConfig cfg;
  cfg.sensor = truth;
  write_text(dir.file("wide.yaml"), io::dump_config(cfg, "sensor"));
  const CliRun sim = run_dloam("simulate --scenario urban --frames 12 --seed 4 --config " +
                               dir.file("wide.yaml") + " --out " + dir.file("drive"));
  ASSERT_EQ(sim.status, 0) << sim.output;
  const CliRun check = run_dloam("check " + dir.file("drive") + " --write-sensor " + dir.file("est.yaml"));
  ASSERT_EQ(check.status, 0) << check.output;
  EXPECT_THAT(check.output, HasSubstr("64 beams, elevation -45.00 .. 45.00 deg"));
  EXPECT_THAT(check.output, HasSubstr("no preset resembles it closely"));
  // The file parses back (validated) into the table.
  const SensorConfig est = io::load_config(dir.file("est.yaml")).sensor;
  EXPECT_EQ(est.preset, "custom");
  std::vector<std::size_t> all(64, 1000);
  const Recovery r = compare(truth, all, est, 100);
  EXPECT_EQ(r.found, 64) << r;
  EXPECT_EQ(r.extra, 0) << r;
  EXPECT_LT(r.offset_error, 0.01) << r;
  EXPECT_EQ(est.Horizon_SCAN, 1024);
  const CliRun run = run_dloam("run " + dir.file("drive") + " --config " + dir.file("est.yaml") + " --out " +
                               dir.file("out") + " --detector none --count 4");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("custom preset"));

  // --preset auto does the same inside the run and records the model in config.yaml.
  const CliRun autorun = run_dloam("run " + dir.file("drive") + " --preset auto --out " + dir.file("auto") +
                                   " --detector none --count 4");
  ASSERT_EQ(autorun.status, 0) << autorun.output;
  EXPECT_THAT(autorun.output, HasSubstr("sensor auto: estimated from scans 0 .. 3"));
  EXPECT_THAT(autorun.output, HasSubstr("64 beams"));
  const SensorConfig recorded = io::load_config(dir.file("auto/config.yaml")).sensor;
  EXPECT_EQ(recorded.preset, "custom");
  EXPECT_EQ(recorded.N_scan, 64);
  // sensor: {preset: auto} in a file; its explicit keys override the estimate.
  write_text(dir.file("auto.yaml"),
             "sensor: {preset: auto, max_range: 50.0}\ndeskew: {time_source: azimuth}\n");
  const CliRun fileauto = run_dloam("run " + dir.file("drive") + " --config " + dir.file("auto.yaml") +
                                    " --out " + dir.file("fileauto") + " --detector none --count 2");
  ASSERT_EQ(fileauto.status, 0) << fileauto.output;
  const PipelineConfig used = io::load_config(dir.file("fileauto/config.yaml"));
  EXPECT_EQ(used.sensor.max_range, 50.0);
  EXPECT_EQ(used.sensor.N_scan, 64);
  EXPECT_EQ(used.deskew.time_source, TimeSource::kAzimuth);
}

TEST(SensorEstimateCli, AutoOutsideRunAndCheckAndUnusableScansAreClearErrors) {
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  const CliRun dump = run_dloam("config dump --preset auto");
  EXPECT_NE(dump.status, 0);
  EXPECT_THAT(dump.output, HasSubstr("--write-sensor"));
  const CliRun list = run_dloam("config presets");
  ASSERT_EQ(list.status, 0) << list.output;
  for (const auto& name : sensor_preset_names()) EXPECT_THAT(list.output, HasSubstr(name));
  // A folder of PCD scans of 10 points: check reports the folder fine, but no model to write.
  TempDir dir;
  PointCloud tiny;
  for (int i = 0; i < 10; ++i) tiny.xyz.emplace_back(3.0 + i, 0.5 * i, -1.0);
  std::filesystem::create_directories(dir.file("tiny"));
  io::write_pcd(dir.file("tiny/000000.pcd"), tiny);
  io::write_pcd(dir.file("tiny/000001.pcd"), tiny);
  const CliRun check = run_dloam("check " + dir.file("tiny"));
  EXPECT_EQ(check.status, 0) << check.output;
  EXPECT_THAT(check.output, HasSubstr("not estimated: sensor estimate: only 20 of the 20 points in 2 scans"));
  const CliRun write = run_dloam("check " + dir.file("tiny") + " --write-sensor " + dir.file("est.yaml"));
  EXPECT_NE(write.status, 0);
  EXPECT_THAT(write.output, HasSubstr("tiny"));
  EXPECT_FALSE(std::filesystem::exists(dir.file("est.yaml")));
  const CliRun run = run_dloam("run " + dir.file("tiny") + " --preset auto --out " + dir.file("o"));
  EXPECT_NE(run.status, 0);
  EXPECT_THAT(run.output, HasSubstr("tiny: sensor estimate: only 20"));
}

TEST(SensorEstimateCli, KittiTableRecoveredWithoutRingsAndTracksAsWell) {
  // The HDL-64E of kitti-raw-0005 without its ring order: `check --write-sensor` with KITTI's
  // vertical correction gives the table calibrate-beams fitted from the rings
  // (config/kitti-raw.yaml), and a run with it tracks as well as one with that file.
  const std::string data = DLOAM_KITTI_0005;
  if (!std::filesystem::exists(data + "/velodyne")) GTEST_SKIP() << "no " << data;
  if (!std::filesystem::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  write_text(dir.file("hints.yaml"), "sensor: {preset: auto, vertical_angle_correction_deg: 0.22}\n");
  const CliRun check = run_dloam("check " + data + " --config " + dir.file("hints.yaml") +
                                 " --write-sensor " + dir.file("est.yaml"));
  ASSERT_EQ(check.status, 0) << check.output;
  const SensorConfig fitted = kitti_table();
  std::ifstream in(dir.file("est.yaml"));
  std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const SensorConfig est = io::config_from_yaml_string(yaml, "est.yaml").sensor;
  ASSERT_EQ(est.N_scan, 64);
  for (int k = 0; k < 64; ++k) {
    EXPECT_NEAR(est.beam_elevation_deg(k), fitted.beam_elevation_deg(k), 0.01) << "beam " << k;
    EXPECT_NEAR(est.beam_vertical_offset_m(k), fitted.beam_vertical_offset_m(k), 0.005) << "beam " << k;
  }
  EXPECT_EQ(est.vertical_angle_correction_deg, 0.22);
  EXPECT_EQ(est.Horizon_SCAN, 2048);
  // The run: the estimate plus the de-skew setting of config/kitti-raw.yaml, appended.
  write_text(dir.file("run.yaml"), yaml + "deskew:\n  time_source: azimuth\n");
  auto t_rel = [&](const std::string& config, const std::string& out) {
    const CliRun run = run_dloam("run " + data + " --config " + config + " --out " + dir.file(out) +
                                 " --detector none --count 40 --lengths 5,10");
    EXPECT_EQ(run.status, 0) << run.output;
    const auto j = nlohmann::json::parse(std::ifstream(dir.file(out + "/metrics.json")));
    return j.at("odometry").at("t_rel_pct").get<double>();
  };
  const double with_estimate = t_rel(dir.file("run.yaml"), "est");
  const double with_fit = t_rel(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml", "fit");
  EXPECT_LT(with_estimate, 1.1 * with_fit) << with_estimate << " % vs " << with_fit << " %";
}
