// The config's `input:` section (how recordings are read) as the options of io::open_sequence().
#pragma once

#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam::io {

InputOptions input_options(const InputConfig& config);

}  // namespace dloam::io
