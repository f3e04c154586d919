#include "dloam/io/input_options.hpp"

namespace dloam::io {

InputOptions input_options(const InputConfig& c) {
  InputOptions o;
  o.topic = c.topic;
  o.calibration = c.calibration;
  o.metadata = c.metadata;
  o.scan.returns = c.returns;
  o.scan.cut_azimuth_deg = c.cut_azimuth_deg;
  o.port = static_cast<std::uint16_t>(c.port);
  return o;
}

}  // namespace dloam::io
