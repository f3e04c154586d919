// dloam's data folder: the shipped configurations (config/*.yaml) and CNN models (models/*.pt),
// found at run time, never by a path of the source tree. The first folder holding
// config/default.yaml among:
//   1. the environment variable DLOAM_DATA_DIR (when set, it must be such a folder);
//   2. share/dloam in the folder of the binary that holds this code (the executable, or the
//      Python module) and in each of its parents, nearest first: an installed <prefix>/bin/dloam
//      or <prefix>/lib/python3.11/dist-packages/dloam finds <prefix>/share/dloam, and the build
//      tree holds build/share/dloam;
//   3. the data folder of the install prefix dloam was configured with.
// A configuration's detection.model_path names a model file directly.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace dloam::io {

/// The data folder, or nothing when none of the places holds one. Throws InputError when
/// DLOAM_DATA_DIR is set to a folder without config/default.yaml.
std::optional<std::string> find_data_dir();
/// The data folder; throws InputError listing where it looked and naming DLOAM_DATA_DIR.
std::string data_dir();
/// The places find_data_dir() looks at, in order (for messages and tests).
std::vector<std::string> data_dir_candidates();
/// <data folder>/models, or empty when there is no data folder.
std::string model_dir();

/// The names of the shipped configurations (config/*.yaml without the extension), sorted; empty
/// without a data folder (never throws).
std::vector<std::string> shipped_configs();
/// A `--config` argument: an existing file as it is, else a shipped configuration by name
/// (`kitti-raw` or `kitti-raw.yaml`). Throws InputError naming the argument and the shipped names.
std::string resolve_config_file(const std::string& name_or_path);

}  // namespace dloam::io
