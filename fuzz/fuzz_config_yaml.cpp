// libFuzzer harness: the YAML configuration through the schema (load and validate; a config that
// loads is dumped and must load again to the same dump).
#include <cstddef>
#include <cstdint>

#include "dloam/io/config_yaml.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::PipelineConfig config;
  try {
    config = dloam::io::config_from_yaml_string(input, "fuzz.yaml");
  } catch (const dloam::InputError&) {
    return 0;
  }
  // No InputError is expected from here on: what dump writes, load reads back unchanged.
  const std::string dumped = dloam::io::dump_config(config);
  if (dloam::io::dump_config(dloam::io::config_from_yaml_string(dumped, "dump.yaml")) != dumped)
    __builtin_trap();
  return 0;
}
