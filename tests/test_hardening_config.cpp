// YAML configs with duplicate keys or a second document, and the rules that only `dloam run`
// used to enforce: every command's validation refuses them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dloam/io/config_yaml.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;

TEST(HardeningYaml, DuplicateKeysSecondDocumentsAndRunOnlyRulesAreErrors) {
  const auto error = [](const std::string& yaml) {
    return input_error_of([&] { (void)config_from_yaml_string(yaml, "my.yaml"); });
  };
  EXPECT_THAT(error("mapping:\n  every_n_scans: 2\n  every_n_scans: 3\n"),
              HasSubstr("mapping.every_n_scans"));
  EXPECT_THAT(error("mapping:\n  every_n_scans: 2\n  every_n_scans: 3\n"), HasSubstr("twice"));
  EXPECT_THAT(error("mapping: {max_iterations: 5}\nmapping: {max_iterations: 6}\n"), HasSubstr("my.yaml:2"));
  EXPECT_THAT(error("threads: 2\n---\nthreads: 3\n"), HasSubstr("my.yaml:2: a second YAML document"));
  EXPECT_THAT(error("---\nthreads: 2\n...\nthreads: 3\n"), HasSubstr("my.yaml:4: a second YAML document"));
  EXPECT_THAT(error("--- {threads: 2}\n--- {threads: 3}\n"), HasSubstr("my.yaml:2"));
  EXPECT_THAT(error("? [a, b]\n: 1\n"), HasSubstr("my.yaml"));
  // What `dloam run` enforces, every command's validation enforces.
  EXPECT_THAT(error("mapping: {every_n_scans: 1, latency_scans: 3}\n"), HasSubstr("latency_scans"));
  for (const char* leaf : {"mapping: {map_leaf_size: 1e-5}\n", "mapping: {edge_leaf_size: 1e-9}\n",
                           "mapping: {plane_leaf_size: 1e-9}\n", "features: {plane_leaf_size: 1e-9}\n"}) {
    const std::string msg = error(leaf);
    EXPECT_THAT(msg, HasSubstr("leaf_size"));
    EXPECT_THAT(msg, HasSubstr("overflow"));
  }
  EXPECT_THAT(error("sensor: {max_range: 1e9}\n"), HasSubstr("sensor.max_range"));
  EXPECT_NO_THROW((void)config_from_yaml_string("mapping: {map_leaf_size: 0.001}\n"));
  EXPECT_NO_THROW((void)config_from_yaml_string("---\nthreads: 2\n"));  // one document with its marker
  EXPECT_NO_THROW((void)config_from_yaml_string("%YAML 1.2\n---\nthreads: 2\n...\n# the end\n"));
  EXPECT_NO_THROW((void)config_from_yaml_string("# nothing but comments\n\n"));
  EXPECT_NO_THROW((void)config_from_yaml_string("sensor:\n  preset: VLP-16\n  # --- not a marker here\n"));
}

TEST(HardeningYaml, DevicesAndFilesLargerThanAnySaneConfigAreRefusedBeforeParsing) {
  EXPECT_THAT(input_error_of([&] { (void)load_config("/dev/zero"); }), HasSubstr("/dev/zero: is a device"));
  // A 10 MB list took 650 MB of memory to parse; a config over 1 MiB is refused unread.
  TempDir dir;
  std::string list = "sensor: {beam_elevations_deg: [";
  while (list.size() < (2u << 20)) list += "1.0, ";
  write_text(dir.file("big.yaml"), list + "1.0]}\n");
  const std::string big = input_error_of([&] { (void)load_config(dir.file("big.yaml")); });
  EXPECT_THAT(big, HasSubstr("big.yaml"));
  EXPECT_THAT(big, HasSubstr("larger than"));
}

TEST(HardeningYaml, FuzzFindingsAreErrorsNotHangs) {
  // yaml-cpp 0.7's LoadAll() never returned on "," (found by fuzz/fuzz_config_yaml.cpp in 10 s).
  for (const char* text : {",", "a: 1\n,", ",\n,\n"})
    EXPECT_THAT(input_error_of([&] { (void)config_from_yaml_string(text, "f.yaml"); }), HasSubstr("f.yaml"));
}
