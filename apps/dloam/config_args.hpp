// The configuration options shared by every command that builds a pipeline configuration:
//   --config FILE|NAME  a YAML file, or a configuration shipped in the data folder by name
//                       (kitti-raw, vlp16, ...: `dloam config presets` lists them)
//   --preset NAME       a sensor preset of the table in core/sensor_presets.cpp
// The file's keys override the preset's (io::config_from). --config is resolved to a file when
// the command line is parsed, so an unknown name stops with the list of shipped ones.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace dloam::app {

struct ConfigArgs {
  std::string config_path;  ///< resolved: an existing file, or empty
  std::string preset;
};

/// Help texts where a command uses the options for something narrower (defaults: the full config).
struct ConfigHelp {
  std::string config;        ///< empty: "YAML config over the preset ..."
  std::string preset;        ///< empty: "sensor preset: <the table's names>"; "{presets}" is replaced by them
  bool preset_auto = false;  ///< mention --preset auto (the model estimated from the data)
  std::string preset_default;  ///< shown as the default (e.g. HDL-64E); empty: none
};

void add_config_options(CLI::App* cmd, ConfigArgs& args, const ConfigHelp& help = {});

/// The --config transform alone (for commands whose --config takes a list): a shipped name becomes
/// its file (add it with ->transform(), not ->check(), which would drop the resolved path).
CLI::Validator config_file_validator();

}  // namespace dloam::app
