// Hesai angle-correction CSV: per channel its 1-based id, elevation (deg) and azimuth offset
// (deg), as Hesai ships it with each unit and as the sensor serves it. The built-in tables are
// the models' nominal ones (hesai_tables.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "dloam/drivers/hesai_model.hpp"

namespace dloam::drivers::hesai {

struct Calibration {
  std::string source;                 ///< the file, or "built-in PandarXT32 table"
  std::vector<double> elevation_deg;  ///< channel 1 first
  std::vector<double> azimuth_deg;    ///< azimuth offset added to the block azimuth

  [[nodiscard]] int channels() const { return static_cast<int>(elevation_deg.size()); }
};

/// Parses the CSV text. Accepted: an optional header line before the first channel line (any
/// line whose first field is not a number: "Laser id,Elevation,Azimuth", "Channel,Elevation,
/// Azimuth", ...), a UTF-8 byte-order mark, CRLF line ends, blank lines, spaces around fields and
/// channel lines in any order. Every channel 1..N must appear exactly once. Throws InputError
/// "<source>:<line>: <problem>" on a line that is not three fields "id,elevation,azimuth" with
/// finite numbers, a duplicate or out-of-range id, and "<source>: ..." on a missing id or no
/// channel at all.
Calibration parse_calibration(std::string_view text, const std::string& source);
/// parse_calibration of a file; throws InputError when it cannot be read.
Calibration read_calibration(const std::string& path);
/// The model's nominal table.
Calibration nominal_calibration(Model model);
/// Throws InputError naming `calibration.source` when it does not fit `model`: another channel
/// count, or a channel more than 2 deg from the model's nominal angles (a table of another model;
/// units of one model differ from the nominal table by tenths of a degree).
void check_calibration(const Calibration& calibration, Model model);

}  // namespace dloam::drivers::hesai
