// YAML configuration: dump/load round trips, presets, shipped config files, and every error
// case (unknown key, wrong type, inconsistent sensor, out-of-range value) naming file and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_schema.hpp"
#include "dloam/io/config_yaml.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {
const std::string kConfigDir = std::string(DLOAM_SOURCE_DIR) + "/config/";

// The braces below list fewer initializers than fields on purpose (clang warns of that).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
/// Number of fields of an aggregate: the most arguments `T{...}` accepts (C++17 has no reflection).
struct AnyField {
  template <class T>
  operator T&() const;  // never called: only used in unevaluated braces
};
template <class T, class... A>
constexpr auto accepts(int) -> decltype(void(T{std::declval<A>()...}), true) {
  return true;
}
template <class T, class... A>
constexpr bool accepts(...) {
  return false;
}
template <class T, class... A>
constexpr std::size_t field_count() {
  if constexpr (accepts<T, A..., AnyField>(0)) {
    return field_count<T, A..., AnyField>();
  } else {
    return sizeof...(A);
  }
}

/// Number of keys the schema table lists for a struct.
struct KeyCounter {
  std::size_t keys = 0;
  template <class T, class C>
  void operator()(const char*, T&, const char*, const C&) {
    ++keys;
  }
  template <class S>
  void group(const char*, S&, const char*) {
    ++keys;
  }
};
template <class S>
std::size_t schema_keys() {
  S s;
  KeyCounter counter;
  detail::visit(s, counter);
  return counter.keys;
}

/// "" when equal, else the first differing line of `actual` vs `expected` (short test output).
std::string first_difference(const std::string& actual, const std::string& expected) {
  std::istringstream a(actual), e(expected);
  std::string la, le;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(a, la)),
               more_e = static_cast<bool>(std::getline(e, le));
    if (!more_a && !more_e) return "";
    if (la != le || more_a != more_e)
      return "line " + std::to_string(line) + ": '" + (more_a ? la : "<end>") + "' but expected '" +
             (more_e ? le : "<end>") + "'";
  }
}

/// Writes `yaml` to a temp file and returns the InputError message of loading it.
std::string load_error(const TempDir& dir, const std::string& name, const std::string& yaml) {
  write_text(dir.file(name), yaml);
  return input_error_of([&] { load_config(dir.file(name)); });
}
}  // namespace

TEST(Config, TheMapsEdgeLineRatioIsChosenByTheSensorUnlessGiven) {
  const PipelineConfig c = default_config();
  EXPECT_EQ(c.mapping.edge_line_ratio, 0.0);  // by the sensor
  EXPECT_EQ(c.odometry.edge_line_ratio, 3.0);
  EXPECT_EQ(edge_line_ratio_for(0.0, 64, true), 10.0);
  EXPECT_EQ(edge_line_ratio_for(0.0, 128, true), 10.0);
  EXPECT_EQ(edge_line_ratio_for(0.0, 64, false), 3.0);  // handheld, legged
  EXPECT_EQ(edge_line_ratio_for(0.0, 32, true), 3.0);
  EXPECT_EQ(edge_line_ratio_for(0.0, 16, true), 3.0);
  EXPECT_EQ(edge_line_ratio_for(5.0, 16, false), 5.0);
  EXPECT_EQ(config_from_yaml_string("mapping: {edge_line_ratio: 4}").mapping.edge_line_ratio, 4.0);
}

TEST(Config, EveryFieldOfConfigHppHasAYamlKey) {
  // A field added to a module config needs its line in dloam/io/config_schema.hpp.
  EXPECT_EQ(schema_keys<SensorConfig>(), field_count<SensorConfig>());
  // SegmentationConfig is GroundConfig + ClusteringConfig (its two bases count as two aggregate members).
  EXPECT_EQ(schema_keys<SegmentationConfig>(), field_count<GroundConfig>() + field_count<ClusteringConfig>());
  EXPECT_EQ(schema_keys<PreRegistrationConfig>(), field_count<PreRegistrationConfig>());
  EXPECT_EQ(schema_keys<DeskewConfig>(), field_count<DeskewConfig>());
  EXPECT_EQ(schema_keys<DetectionConfig>(), field_count<DetectionConfig>());
  EXPECT_EQ(schema_keys<FeatureConfig>(), field_count<FeatureConfig>());
  EXPECT_EQ(schema_keys<OdometryConfig>(), field_count<OdometryConfig>());
  EXPECT_EQ(schema_keys<MappingConfig>(), field_count<MappingConfig>());
  EXPECT_EQ(schema_keys<PipelineConfig>(), field_count<PipelineConfig>());
  EXPECT_EQ(field_count<DeskewConfig>(), 3u);  // the counter itself works
}

TEST(Config, DumpThenLoadGivesTheSameConfigForEveryPreset) {
  for (const auto& preset : sensor_preset_names()) {
    const auto config = default_config(preset);
    const std::string yaml = dump_config(config);
    const auto back = config_from_yaml_string(yaml, "dump", PipelineConfig{});
    EXPECT_EQ(dump_config(back), yaml) << preset;
    EXPECT_EQ(back.sensor.N_scan, config.sensor.N_scan);
    EXPECT_EQ(back.sensor.beam_elevations_deg, config.sensor.beam_elevations_deg);
  }
}

TEST(Config, NonDefaultValuesSurviveTheRoundTrip) {
  auto config = default_config("VLP-16");
  config.sensor.vertical_angle_correction_deg = 0.205;
  config.detection.detector = Detector::kCnn;
  config.detection.model_path = "models/my model: v2.bin";
  config.deskew.enabled = false;
  config.features.c_th = 0.1 + 1e-12;
  config.threads = 7;
  const auto back = config_from_yaml_string(dump_config(config));
  EXPECT_EQ(back.sensor.vertical_angle_correction_deg, 0.205);
  EXPECT_EQ(back.detection.detector, Detector::kCnn);
  EXPECT_EQ(back.detection.model_path, "models/my model: v2.bin");
  EXPECT_FALSE(back.deskew.enabled);
  EXPECT_EQ(back.features.c_th, 0.1 + 1e-12);
  EXPECT_EQ(back.threads, 7);
  for (const char* path : {"On", "a \"quoted\" \\ path", "12", "#hash", ""}) {
    config.detection.model_path = path;
    EXPECT_EQ(config_from_yaml_string(dump_config(config)).detection.model_path, path);
  }
}

TEST(Config, LongAndControlCharacterStringsSurviveTheRoundTrip) {
  auto config = default_config();
  const std::string long_name(300, 'H');                        // longer than a line, no commas
  const std::string long_list = "a, " + std::string(200, 'b');  // commas inside a string
  const std::string controls = std::string("tab\there\nnew line\r\x01\x7f") + '\0' + "end";
  for (const std::string& s : {long_name, long_list, controls, std::string("caf\xc3\xa9")}) {
    config.input.topic = s;
    config.input.calibration = s;
    const std::string yaml = dump_config(config);
    const auto back = config_from_yaml_string(yaml, "dump");
    EXPECT_EQ(back.input.topic, s);
    EXPECT_EQ(back.input.calibration, s);
    EXPECT_EQ(dump_config(back), yaml);
  }
}

TEST(Config, PresetThenExplicitKeysOverride) {
  const auto c = config_from_yaml_string(
      "sensor: {preset: vlp-16, max_range: 80}\nmapping:\n  every_n_scans: 5\nthreads: 1\n");
  EXPECT_EQ(c.sensor.preset, "VLP-16");
  EXPECT_EQ(c.sensor.N_scan, 16);
  EXPECT_EQ(c.sensor.max_range, 80.0);
  EXPECT_EQ(c.sensor.min_range, sensor_preset("VLP-16").min_range);
  EXPECT_EQ(c.mapping.every_n_scans, 5);
  EXPECT_EQ(c.threads, 1);
  EXPECT_EQ(c.mapping.max_iterations, MappingConfig{}.max_iterations);
  // An empty document is the defaults.
  EXPECT_EQ(dump_config(config_from_yaml_string("")), dump_config(default_config()));
}

TEST(Config, ShippedDefaultYamlIsExactlyTheBuiltInDefaults) {
  const std::string path = kConfigDir + "default.yaml";
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const std::string expected = dump_config(default_config());
  // Loaded over a different base, so every value must come from the file.
  EXPECT_EQ(first_difference(dump_config(load_config(path, default_config("OS1-128"))), expected), "")
      << "config/default.yaml no longer holds the defaults of config.hpp";
  EXPECT_EQ(first_difference(read_file(path), expected), "")
      << "regenerate with: dloam config dump > config/default.yaml";
}

TEST(Config, ShippedPresetFilesMatchTheBuiltInPresets) {
  const std::pair<const char*, const char*> files[] = {{"hdl64e.yaml", "HDL-64E"},
                                                       {"hdl32e.yaml", "HDL-32E"},
                                                       {"vlp16.yaml", "VLP-16"},
                                                       {"os1-64.yaml", "OS1-64"},
                                                       {"os1-128.yaml", "OS1-128"}};
  for (const auto& [file, preset] : files) {
    const auto config = load_config(kConfigDir + file);
    EXPECT_EQ(first_difference(dump_config(config), dump_config(default_config(preset))), "") << file;
    EXPECT_THAT(read_file(kConfigDir + file), Not(HasSubstr("mapping:"))) << file << " has only the sensor";
  }
}

TEST(Config, UnknownKeysAreErrorsNamingFileAndKeyPath) {
  TempDir dir;
  auto msg = load_error(dir, "typo.yaml", "sensor:\n  N_scna: 32\n");
  EXPECT_THAT(msg, HasSubstr("typo.yaml:2"));
  EXPECT_THAT(msg, HasSubstr("sensor.N_scna"));
  EXPECT_THAT(msg, HasSubstr("unknown key"));
  msg = load_error(dir, "section.yaml", "odometri:\n  beta: 0.2\n");
  EXPECT_THAT(msg, HasSubstr("section.yaml"));
  EXPECT_THAT(msg, HasSubstr("odometri"));
}

TEST(Config, WrongTypesAreErrorsNamingFileAndKeyPath) {
  TempDir dir;
  auto msg = load_error(dir, "type.yaml", "features:\n  S: ten\n");
  EXPECT_THAT(msg, HasSubstr("type.yaml:2"));
  EXPECT_THAT(msg, HasSubstr("features.S"));
  EXPECT_THAT(msg, HasSubstr("integer"));
  msg = load_error(dir, "float_for_int.yaml", "mapping: {every_n_scans: 2.5}\n");
  EXPECT_THAT(msg, HasSubstr("mapping.every_n_scans"));
  msg = load_error(dir, "bool.yaml", "deskew: {enabled: maybe}\n");
  EXPECT_THAT(msg, HasSubstr("deskew.enabled"));
  msg = load_error(dir, "list.yaml", "sensor: {beam_elevations_deg: [1.0, x]}\n");
  EXPECT_THAT(msg, HasSubstr("sensor.beam_elevations_deg[1]"));
  msg = load_error(dir, "map.yaml", "mapping: 3\n");
  EXPECT_THAT(msg, HasSubstr("map.yaml"));
  EXPECT_THAT(msg, HasSubstr("mapping"));
  msg = load_error(dir, "syntax.yaml", "sensor: [\n");
  EXPECT_THAT(msg, HasSubstr("syntax.yaml"));
}

TEST(Config, InconsistentOrOutOfRangeValuesAreErrors) {
  TempDir dir;
  // HDL-64E lists 64 beam elevations; N_scan 32 contradicts them.
  auto msg = load_error(dir, "beams.yaml", "sensor: {preset: HDL-64E, N_scan: 32}\n");
  EXPECT_THAT(msg, HasSubstr("beams.yaml"));
  EXPECT_THAT(msg, HasSubstr("beam_elevations_deg"));
  msg = load_error(dir, "range.yaml", "preregistration: {xi_1: 1.5}\n");
  EXPECT_THAT(msg, HasSubstr("range.yaml"));
  EXPECT_THAT(msg, HasSubstr("preregistration.xi_1"));
  msg = load_error(dir, "choice.yaml", "detection: {detector: magic}\n");
  EXPECT_THAT(msg, HasSubstr("detection.detector"));
  msg = load_error(dir, "preset.yaml", "sensor: {preset: HDL-99}\n");
  EXPECT_THAT(msg, HasSubstr("sensor.preset"));
  msg = load_error(dir, "odd.yaml", "features: {S: 7}\n");
  EXPECT_THAT(msg, HasSubstr("features.S"));
  msg = load_error(dir, "line.yaml", "mapping: {edge_line_ratio: 0.5}\n");
  EXPECT_THAT(msg, HasSubstr("line.yaml: mapping.edge_line_ratio must be 0 (by the sensor) or at least 1"));
  EXPECT_THAT(input_error_of([&] { load_config(dir.file("absent.yaml")); }), HasSubstr("absent.yaml"));
  // Explicit uniform beams make N_scan 32 valid.
  EXPECT_EQ(
      config_from_yaml_string("sensor: {preset: HDL-64E, N_scan: 32, beam_elevations_deg: []}").sensor.N_scan,
      32);
}

TEST(Config, DumpOfOneSection) {
  const std::string sensor = dump_config(default_config("OS1-64"), "sensor");
  EXPECT_THAT(sensor, HasSubstr("preset: OS1-64"));
  EXPECT_THAT(sensor, Not(HasSubstr("mapping")));
  EXPECT_THAT(sensor, Not(HasSubstr("threads")));
  EXPECT_THAT(input_error_of([] { dump_config(default_config(), "mappin"); }), HasSubstr("mappin"));
}
