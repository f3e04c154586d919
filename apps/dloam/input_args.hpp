// The command-line options of how a recording is read (--topic, --calibration, --metadata,
// --returns, --cut-azimuth, --port), shared by run, check and convert; they override the
// config's `input:` section.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "dloam/pipeline/config.hpp"

namespace dloam::app {

struct InputArgs {
  std::string topic, calibration, metadata, returns;
  std::optional<double> cut_azimuth;
  std::optional<int> port;
};

void add_input_options(CLI::App* cmd, InputArgs& args);

/// The config's input section with the given options applied over it (io::input_options()
/// turns it into what io::open_sequence() takes).
InputConfig apply_input_args(InputConfig config, const InputArgs& args);

}  // namespace dloam::app
