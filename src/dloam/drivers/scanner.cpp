#include "dloam/drivers/scanner.hpp"

namespace dloam::drivers {}  // namespace dloam::drivers
