// Text or binary encoding of the point-cloud file formats (PCD, PLY).
#pragma once

namespace dloam::io {

enum class Encoding { kAscii, kBinary };

}  // namespace dloam::io
