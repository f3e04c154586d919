// Strict parsing helpers shared by the text formats.
#include "dloam/io/text_util.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace dloam::io::detail {

void fail(const std::string& path, const std::string& what) { throw InputError(path + ": " + what); }

void fail_at(const std::string& path, std::size_t line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    start = end + 1;
  }
  return lines;
}

void check_point_distance(const std::string& path, std::size_t i, const Vec3& p) {
  if (p.cwiseAbs().maxCoeff() > kMaxPointDistance)
    fail(path,
         "point " + std::to_string(i) + " at (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) +
             ", " + std::to_string(p.z()) +
             ") is farther than 1e6 m from the sensor: no LiDAR return (a wrong unit or record layout?)");
}

bool is_blank_or_comment(std::string_view line) {
  const auto first = line.find_first_not_of(" \t");
  return first == std::string_view::npos || line[first] == '#';
}

std::vector<std::string_view> split(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < text.size() && text[j] != ' ' && text[j] != '\t' && text[j] != '\r') ++j;
    if (j > i) tokens.push_back(text.substr(i, j - i));
    i = j;
  }
  return tokens;
}

bool parse_doubles(std::string_view text, std::vector<double>& out, std::string& error,
                   bool allow_non_finite) {
  out.clear();
  for (const auto token : split(text)) {
    double v = 0.0;
    const char* begin = token.data();
    if (!token.empty() && token.front() == '+') ++begin;  // from_chars rejects a leading '+'
    const auto [ptr, ec] = std::from_chars(begin, token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      error = "'" + std::string(token) + "' is not a number";
      return false;
    }
    if (!allow_non_finite && !std::isfinite(v)) {
      error = "'" + std::string(token) + "' is not finite";
      return false;
    }
    out.push_back(v);
  }
  return true;
}

std::size_t parse_count(const std::string& path, std::size_t line, std::string_view token) {
  std::size_t v = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size() || token.empty()) {
    const std::string what = "'" + std::string(token) + "' is not a non-negative integer";
    if (line == 0) fail(path, what);
    fail_at(path, line, what);
  }
  return v;
}

Pose pose_from_row_major(const double* v) {
  Pose pose = Pose::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = v[4 * r + c];
  return pose;
}

double orthonormality_error(const Eigen::Matrix3d& R) {
  const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return R.determinant() > 0.0 ? err : std::max(err, 1.0);
}

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9e", v);
  return buf;
}

}  // namespace dloam::io::detail
