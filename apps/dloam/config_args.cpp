#include "config_args.hpp"

#include <string>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"
#include "dloam/io/data_dir.hpp"

namespace dloam::app {

CLI::Validator config_file_validator() {
  return CLI::Validator(
      [](std::string& value) {
        try {
          value = io::resolve_config_file(value);
          return std::string();
        } catch (const InputError& e) {
          return std::string(e.what());
        }
      },
      "FILE|NAME");
}

void add_config_options(CLI::App* cmd, ConfigArgs& args, const ConfigHelp& help) {
  std::string config_help = help.config;
  if (config_help.empty()) {
    config_help = "YAML config over the preset (see `dloam config dump`), or the name of a shipped one";
    std::string names;
    for (const std::string& n : io::shipped_configs()) names += (names.empty() ? "" : ", ") + n;
    if (!names.empty()) config_help += " (" + names + ")";
  }
  cmd->add_option("--config,-c", args.config_path, config_help)->transform(config_file_validator());

  std::string preset_help = help.preset.empty() ? "sensor preset: {presets}" : help.preset;
  if (const auto at = preset_help.find("{presets}"); at != std::string::npos)
    preset_help.replace(at, 9, sensor_preset_list());
  if (help.preset_auto)
    preset_help += "; or auto: estimated from the first scans (see `dloam check --write-sensor`)";
  auto* preset = cmd->add_option("--preset", args.preset, preset_help);
  if (!help.preset_default.empty()) {
    args.preset = help.preset_default;
    preset->capture_default_str();
  }
}

}  // namespace dloam::app
