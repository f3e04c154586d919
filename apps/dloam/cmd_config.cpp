// `dloam config dump`: prints the full YAML configuration (defaults, a sensor preset, a config
// file on top), every parameter with a comment, ready to edit and pass to `dloam run --config`.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "dloam/io/config_yaml.hpp"

namespace dloam::app {
namespace {

struct DumpArgs {
  std::string preset, config_path, section;
};

void run_dump(const DumpArgs& a) {
  fmt::print("{}", io::dump_config(io::config_from(a.preset, a.config_path), a.section));
}

}  // namespace

void register_config(CLI::App& app) {
  auto* cmd = app.add_subcommand("config", "print and check YAML configurations");
  cmd->require_subcommand(1);
  auto args = std::make_shared<DumpArgs>();
  auto* dump = cmd->add_subcommand("dump", "print the full configuration as commented YAML");
  dump->add_option("--preset", args->preset,
                   "start from this sensor preset: HDL-64E, HDL-32E, VLP-16, OS1-64, OS1-128");
  dump->add_option("--config,-c", args->config_path,
                   "YAML file applied on top (validated; unknown keys are errors)")
      ->check(CLI::ExistingFile);
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
}

}  // namespace dloam::app
