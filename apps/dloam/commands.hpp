// Each subcommand of the `dloam` tool lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

namespace dloam::app {

void register_simulate(CLI::App& app);
void register_eval(CLI::App& app);
void register_check(CLI::App& app);
void register_config(CLI::App& app);
void register_run(CLI::App& app);

}  // namespace dloam::app
