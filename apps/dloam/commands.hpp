// Each subcommand of the `dloam` tool lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

namespace dloam::app {

void register_simulate(CLI::App& app);
void register_thin(CLI::App& app);
void register_eval(CLI::App& app);
void register_check(CLI::App& app);
void register_config(CLI::App& app);
void register_run(CLI::App& app);
void register_clean(CLI::App& app);
void register_calibrate(CLI::App& app);  ///< calibrate-beams
void register_convert(CLI::App& app);
void register_report(CLI::App& app);
void register_train(CLI::App& app);  ///< only with LibTorch (DLOAM_WITH_TORCH)
void register_sweep(CLI::App& app);  ///< only with LibTorch (DLOAM_WITH_TORCH)

}  // namespace dloam::app
