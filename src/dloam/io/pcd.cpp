// PCD reader/writer (ascii and binary). Header fields: VERSION FIELDS SIZE TYPE COUNT WIDTH
// HEIGHT VIEWPOINT POINTS DATA.
#include "dloam/io/pcd.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/fields.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;
using detail::Field;
using detail::Layout;
using detail::ScalarType;

namespace {
struct PcdHeader {
  Layout layout;
  std::size_t points = 0;
  std::string data;             ///< ascii | binary | binary_compressed
  std::size_t data_offset = 0;  ///< byte offset of the first data byte
  std::size_t data_line = 0;    ///< 1-based line of the first ascii data line
};

ScalarType pcd_type(const std::string& path, char type, int size) {
  if (type == 'F' && size == 4) return ScalarType::kF32;
  if (type == 'F' && size == 8) return ScalarType::kF64;
  if (type == 'I' || type == 'U') {
    const bool u = type == 'U';
    if (size == 1) return u ? ScalarType::kU8 : ScalarType::kI8;
    if (size == 2) return u ? ScalarType::kU16 : ScalarType::kI16;
    if (size == 4) return u ? ScalarType::kU32 : ScalarType::kI32;
    if (size == 8) return u ? ScalarType::kU64 : ScalarType::kI64;
  }
  fail(path, std::string("unsupported field TYPE ") + type + " with SIZE " + std::to_string(size));
}

/// a * b, or nullopt when it overflows.
std::optional<std::size_t> checked_product(std::size_t a, std::size_t b) {
  if (a != 0 && b > std::numeric_limits<std::size_t>::max() / a) return std::nullopt;
  return a * b;
}

constexpr std::size_t kMaxFields = 1024;         // fields per record
constexpr std::size_t kMaxFieldCount = 1 << 16;  // COUNT of one field

PcdHeader parse_header(const std::string& path, const std::string& bytes) {
  std::map<std::string, std::vector<std::string_view>> keys;
  std::size_t pos = 0, line = 0;
  PcdHeader h;
  while (pos < bytes.size() && h.data.empty()) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    const std::string_view text(bytes.data() + pos, end - pos);
    ++line;
    pos = end + 1;
    if (detail::is_blank_or_comment(text)) continue;
    auto tokens = detail::split(text);
    if (tokens.empty()) continue;
    const std::string key(tokens[0]);
    tokens.erase(tokens.begin());
    if (key == "DATA") {
      if (tokens.size() != 1) detail::fail_at(path, line, "DATA needs one value");
      h.data = std::string(tokens[0]);
    } else if (!keys.emplace(key, tokens).second) {
      detail::fail_at(path, line, "header line " + key + " appears twice");
    }
  }
  if (h.data.empty()) fail(path, "not a PCD file (no DATA line in the header)");
  h.data_offset = std::min(pos, bytes.size());
  h.data_line = line + 1;
  if (h.data == "binary_compressed")
    fail(path, "DATA binary_compressed is unsupported (use ascii or binary)");
  if (h.data != "ascii" && h.data != "binary") fail(path, "unknown DATA '" + h.data + "'");
  const auto& names = keys["FIELDS"];
  const auto& sizes = keys["SIZE"];
  const auto& types = keys["TYPE"];
  auto counts = keys["COUNT"];
  if (names.empty()) fail(path, "header has no FIELDS");
  if (names.size() > kMaxFields) fail(path, "more than " + std::to_string(kMaxFields) + " FIELDS");
  if (counts.empty()) counts.assign(names.size(), "1");
  if (sizes.size() != names.size() || types.size() != names.size() || counts.size() != names.size())
    fail(path, "FIELDS, SIZE, TYPE and COUNT must have the same number of entries");
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (types[i].size() != 1) fail(path, "bad TYPE '" + std::string(types[i]) + "'");
    const std::size_t size = detail::parse_count(path, 0, sizes[i]);
    const std::size_t count = detail::parse_count(path, 0, counts[i]);
    if (count == 0 || count > kMaxFieldCount)
      fail(path, "field " + std::string(names[i]) + " has COUNT " + std::to_string(count) + " (1 to " +
                     std::to_string(kMaxFieldCount) + " allowed)");
    h.layout.add(std::string(names[i]),
                 pcd_type(path, types[i][0], static_cast<int>(std::min<std::size_t>(size, 16))), count);
  }
  if (!h.layout.find({"x"}) || !h.layout.find({"y"}) || !h.layout.find({"z"}))
    fail(path, "FIELDS must include x y z");
  auto number = [&](const char* key, std::size_t fallback) {
    const auto it = keys.find(key);
    if (it == keys.end() || it->second.empty()) return fallback;
    if (it->second.size() != 1) fail(path, std::string(key) + " needs one value");
    return detail::parse_count(path, 0, it->second[0]);
  };
  const std::size_t width = number("WIDTH", 0), height = number("HEIGHT", 1);
  const auto product = checked_product(width, height);
  if (!product) fail(path, "WIDTH * HEIGHT overflows");
  h.points = *product;
  if (keys.count("POINTS")) {
    h.points = number("POINTS", 0);
    if (keys.count("WIDTH") && h.points != *product)
      fail(path, "POINTS " + std::to_string(h.points) + " != WIDTH * HEIGHT " + std::to_string(*product));
  }
  // The data must hold the points before anything is allocated for them: a binary record is
  // `stride` bytes, an ascii line at least one character and a separator per value.
  const std::size_t available = bytes.size() - h.data_offset;
  const auto need = h.data == "binary" ? checked_product(h.points, h.layout.stride)
                                       : checked_product(h.points, 2 * h.layout.columns);
  const std::size_t slack = h.data == "binary" ? 0 : 1;  // the last ascii line may lack its newline
  if (!need || *need > available + slack)
    fail(path, "truncated: " + std::to_string(h.points) + " points need " +
                   (need ? (h.data == "binary" ? "" : "at least ") + std::to_string(*need)
                         : std::string("more than 2^64")) +
                   " data bytes, found " + std::to_string(available));
  return h;
}

/// A double as float32; InputError when it is outside the float range (the cast would be undefined).
float to_float(const std::string& path, std::size_t i, const char* what, double v) {
  if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    fail(path,
         "point " + std::to_string(i) + " has " + what + " " + std::to_string(v) + " (not a finite float32)");
  return static_cast<float>(v);
}

}  // namespace

std::vector<float> to_sweep_fraction(const std::vector<double>& t) {
  if (t.empty()) return {};
  const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
  const bool fractions = *lo >= 0.0 && *hi < 1.0 && *hi - *lo >= 0.5;
  std::vector<float> out(t.size(), 0.0f);
  // Halves keep the span finite for any finite times.
  const double half_span = 0.5 * *hi - 0.5 * *lo;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double f =
        fractions ? t[i] : (half_span > 0.0 ? (0.5 * t[i] - 0.5 * *lo) / half_span * (1.0 - 1e-6) : 0.0);
    out[i] = std::clamp(static_cast<float>(f), 0.0f, std::nextafter(1.0f, 0.0f));
  }
  return out;
}

PointCloud parse_pcd(const std::string& bytes, const std::string& path, ScanInfo* info) {
  const PcdHeader h = parse_header(path, bytes);
  if (h.points == 0) fail(path, "empty scan (0 points)");
  const Field fx = *h.layout.find({"x"}), fy = *h.layout.find({"y"}), fz = *h.layout.find({"z"});
  const auto fi = h.layout.find({"intensity"});
  const auto ft = h.layout.find({"t", "time"});
  PointCloud cloud;
  cloud.xyz.reserve(h.points);
  if (fi) cloud.intensity.reserve(h.points);
  std::vector<double> times;
  if (ft) times.reserve(h.points);
  std::vector<std::size_t> kept;  // file index of each point read, once a point was dropped
  bool dropped_any = false;
  std::vector<double> values;  // one ascii record, or unused
  auto get = [&](const Field& f, const char* record) {
    return h.data == "binary" ? detail::load_scalar(f.type, record + f.offset) : values[f.column];
  };
  std::size_t pos = h.data_offset, line = h.data_line;
  for (std::size_t i = 0; i < h.points; ++i, ++line) {
    const char* record = bytes.data() + pos;
    if (h.data == "binary") {
      pos += h.layout.stride;
    } else {
      if (pos >= bytes.size())
        fail(path, "truncated: POINTS is " + std::to_string(h.points) + " but only " + std::to_string(i) +
                       " data lines were found");
      std::size_t end = bytes.find('\n', pos);
      if (end == std::string::npos) end = bytes.size();
      const std::string_view text(bytes.data() + pos, end - pos);
      pos = end + 1;
      std::string error;
      if (!detail::parse_doubles(text, values, error, /*allow_non_finite=*/true))
        detail::fail_at(path, line, error);
      if (values.size() != h.layout.columns)
        detail::fail_at(
            path, line,
            "expected " + std::to_string(h.layout.columns) + " values, got " + std::to_string(values.size()));
    }
    const Vec3 p(get(fx, record), get(fy, record), get(fz, record));
    if (!p.allFinite()) {  // no return (organised clouds keep the pixel): dropped and counted
      if (!dropped_any) {
        kept.resize(cloud.size());
        for (std::size_t k = 0; k < kept.size(); ++k) kept[k] = k;
        dropped_any = true;
      }
      continue;
    }
    detail::check_point_distance(path, i, p);
    if (dropped_any) kept.push_back(i);
    cloud.xyz.push_back(p);
    if (fi) cloud.intensity.push_back(to_float(path, i, "intensity", get(*fi, record)));
    if (ft) {
      const double t = get(*ft, record);
      if (!std::isfinite(t)) fail(path, "point " + std::to_string(i) + " has a NaN or Inf time");
      times.push_back(t);
    }
  }
  if (cloud.empty())
    fail(path,
         "no point with finite coordinates (all " + std::to_string(h.points) + " are NaN/Inf: no returns)");
  if (ft) cloud.time = to_sweep_fraction(times);
  if (info) {
    info->file_points = h.points;
    info->kept = std::move(kept);
  }
  return cloud;
}

PointCloud read_pcd(const std::string& path, ScanInfo* info) {
  return parse_pcd(read_file(path), path, info);
}

void write_pcd(const std::string& path, const PointCloud& cloud, Encoding encoding,
               const std::string& time_field) {
  const bool with_i = cloud.has_intensity(), with_t = cloud.has_time();
  write_atomic(path, [&](std::ostream& out) {
    const std::size_t n_fields = 3 + (with_i ? 1 : 0) + (with_t ? 1 : 0);
    std::string ones, fours, types;
    for (std::size_t k = 0; k < n_fields; ++k) {
      ones += " 1";
      fours += " 4";
      types += " F";
    }
    out << "# .PCD v0.7 - Point Cloud Data file format (written by dloam)\nVERSION 0.7\nFIELDS x y z"
        << (with_i ? " intensity" : "") << (with_t ? " " + time_field : "") << "\nSIZE" << fours << "\nTYPE"
        << types << "\nCOUNT" << ones << "\nWIDTH " << cloud.size()
        << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << cloud.size() << "\nDATA "
        << (encoding == Encoding::kBinary ? "binary" : "ascii") << '\n';
    std::vector<float> record(n_fields);
    char buf[24];
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      std::size_t k = 0;
      for (int a = 0; a < 3; ++a) record[k++] = static_cast<float>(cloud.xyz[i][a]);
      if (with_i) record[k++] = cloud.intensity[i];
      if (with_t) record[k++] = cloud.time[i];
      if (encoding == Encoding::kBinary) {
        out.write(reinterpret_cast<const char*>(record.data()), static_cast<std::streamsize>(4 * n_fields));
        continue;
      }
      for (std::size_t j = 0; j < n_fields; ++j) {
        std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(record[j]));
        out << (j ? " " : "") << buf;
      }
      out << '\n';
    }
  });
}

}  // namespace dloam::io
