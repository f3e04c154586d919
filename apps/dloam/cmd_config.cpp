// `dloam config dump`: prints the full YAML configuration (defaults, a sensor preset, a config
// file on top), every parameter with a comment, ready to edit and pass to `dloam run --config`.
// `dloam config presets`: lists the built-in sensor presets with the source of each table, and the
// configurations shipped in the data folder.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/data_dir.hpp"

namespace dloam::app {
namespace {

struct DumpArgs {
  std::string section;
  ConfigArgs config;
};

void run_dump(const DumpArgs& a) {
  fmt::print("{}", io::dump_config(io::config_from(a.config.preset, a.config.config_path), a.section));
}

void run_presets() {
  for (const SensorPresetInfo& p : sensor_preset_info())
    fmt::print("{:<12} {:>3} beams  {:6.2f} .. {:6.2f} deg  {:>4} columns  {}\n", p.name, p.beams,
               p.lowest_deg, p.highest_deg, p.columns, p.source);
  fmt::print(
      "\nRange limits other than those of HDL-64E, HDL-32E, VLP-16, OS1-64 and OS1-128 are generous round\n"
      "values, not from the tables.\n"
      "Also: custom (a sensor section given by its keys alone) and auto (estimated from the data by\n"
      "dloam run / dloam check; `dloam check SEQUENCE --write-sensor FILE` writes it).\n");
  const auto dir = io::find_data_dir();
  if (!dir) {
    fmt::print("\nNo data folder with the shipped configurations was found (set DLOAM_DATA_DIR).\n");
    return;
  }
  fmt::print("\nShipped configurations (--config NAME), in {}/config:\n", *dir);
  for (const std::string& name : io::shipped_configs()) fmt::print("  {}\n", name);
}

}  // namespace

void register_config(CLI::App& app) {
  auto* cmd = app.add_subcommand("config", "print and check YAML configurations");
  cmd->require_subcommand(1);
  auto args = std::make_shared<DumpArgs>();
  auto* dump = cmd->add_subcommand("dump", "print the full configuration as commented YAML");
  ConfigHelp config_help;
  config_help.preset = "start from this sensor preset: {presets}";
  add_config_options(dump, args->config, config_help);
  dump->add_option(
      "--section", args->section,
      "print only one section: sensor, segmentation, preregistration, deskew, detection, features, "
      "odometry, mapping");
  dump->footer(
      "Examples:\n"
      "  dloam config dump > my.yaml                      # every default, commented\n"
      "  dloam config dump --preset VLP-16 --section sensor\n"
      "  dloam config dump --config my.yaml               # check a file and show the effective values");
  dump->callback([args] { run_dump(*args); });
  auto* presets =
      cmd->add_subcommand("presets",
                          "list the built-in sensor presets (and where their tables come from) and "
                          "the configurations shipped in the data folder");
  presets->callback([] { run_presets(); });
}

}  // namespace dloam::app
