// Hesai angle-correction CSV reader and the check that a table fits the model.
#include "dloam/drivers/hesai_calibration.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "dloam/core/types.hpp"

namespace dloam::drivers::hesai {

namespace {

[[noreturn]] void fail_line(const std::string& source, std::size_t line, const std::string& what) {
  throw InputError(source + ":" + std::to_string(line) + ": " + what);
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool parse_number(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return !token.empty() && result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

bool parse_id(std::string_view token, long& value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return !token.empty() && result.ec == std::errc() && result.ptr == end;
}

}  // namespace

Calibration parse_calibration(std::string_view text, const std::string& source) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  constexpr long kMaxChannels = 512;
  std::vector<double> elevation, azimuth;
  std::vector<std::size_t> defined_on;  // line of each id's definition, 0: not yet
  bool seen_content = false;
  std::size_t line_no = 0, start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (trim(line).empty()) {
      if (end == text.size()) break;
      continue;
    }
    const std::vector<std::string_view> f = split_fields(line);
    long id = 0;
    if (!seen_content) {
      seen_content = true;
      double first_value = 0.0;
      if (!parse_number(f[0], first_value)) continue;  // the header line
    }
    if (f.size() != 3)
      fail_line(source, line_no,
                "expected 3 fields \"id,elevation,azimuth\", got " + std::to_string(f.size()) + ": \"" +
                    std::string(line) + "\"");
    if (!parse_id(f[0], id) || id < 1 || id > kMaxChannels)
      fail_line(source, line_no,
                "channel id \"" + std::string(f[0]) + "\" is not an integer in [1, " +
                    std::to_string(kMaxChannels) + "]");
    double e = 0.0, a = 0.0;
    if (!parse_number(f[1], e) || !(std::abs(e) < 90.0))
      fail_line(source, line_no, "elevation \"" + std::string(f[1]) + "\" is not a number in (-90, 90)");
    if (!parse_number(f[2], a) || !(std::abs(a) <= 360.0))
      fail_line(source, line_no, "azimuth \"" + std::string(f[2]) + "\" is not a number in [-360, 360]");
    const auto index = static_cast<std::size_t>(id - 1);
    if (index >= defined_on.size()) {
      defined_on.resize(index + 1, 0);
      elevation.resize(index + 1, 0.0);
      azimuth.resize(index + 1, 0.0);
    }
    if (defined_on[index] != 0)
      fail_line(source, line_no,
                "channel " + std::to_string(id) + " is defined twice (first on line " +
                    std::to_string(defined_on[index]) + ")");
    defined_on[index] = line_no;
    elevation[index] = e;
    azimuth[index] = a;
    if (end == text.size()) break;
  }
  if (defined_on.empty()) throw InputError(source + ": no channel lines \"id,elevation,azimuth\"");
  for (std::size_t i = 0; i < defined_on.size(); ++i)
    if (defined_on[i] == 0)
      throw InputError(source + ": channel " + std::to_string(i + 1) + " is missing (the ids go up to " +
                       std::to_string(defined_on.size()) + ")");
  Calibration c;
  c.source = source;
  c.elevation_deg = std::move(elevation);
  c.azimuth_deg = std::move(azimuth);
  return c;
}

Calibration read_calibration(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the Hesai angle-correction file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return parse_calibration(text.str(), path);
}

Calibration nominal_calibration(Model model) {
  Calibration c;
  c.source = std::string("built-in ") + model_name(model) + " table";
  for (const ChannelAngle& a : nominal_angles(model)) {
    c.elevation_deg.push_back(a.elevation_deg);
    c.azimuth_deg.push_back(a.azimuth_deg);
  }
  return c;
}

void check_calibration(const Calibration& calibration, Model model) {
  const ModelInfo& info = model_info(model);
  if (calibration.channels() != info.channels)
    throw InputError(calibration.source + ": " + std::to_string(calibration.channels()) +
                     " channels, but a " + info.name + " has " + std::to_string(info.channels));
  constexpr double kTolerance = 2.0;  // deg
  const std::vector<ChannelAngle> nominal = nominal_angles(model);
  for (std::size_t i = 0; i < nominal.size(); ++i) {
    const double de = calibration.elevation_deg[i] - nominal[i].elevation_deg;
    const double da = calibration.azimuth_deg[i] - nominal[i].azimuth_deg;
    if (std::abs(de) > kTolerance || std::abs(da) > kTolerance) {
      std::ostringstream msg;
      msg << calibration.source << ": channel " << i + 1 << " (elevation " << calibration.elevation_deg[i]
          << ", azimuth " << calibration.azimuth_deg[i] << " deg) is more than " << kTolerance
          << " deg from the " << info.name << "'s nominal angles (" << nominal[i].elevation_deg << ", "
          << nominal[i].azimuth_deg << "): not a " << info.name << " angle-correction table";
      throw InputError(msg.str());
    }
  }
}

}  // namespace dloam::drivers::hesai
