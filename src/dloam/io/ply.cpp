// PLY reader/writer (ascii and binary little-endian) for point clouds and maps.
#include "dloam/io/ply.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/fields.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;
using detail::fail_at;
using detail::Field;
using detail::Layout;
using detail::ScalarType;

namespace {
ScalarType ply_type(const std::string& path, std::size_t line, std::string_view name) {
  static const std::map<std::string_view, ScalarType> kTypes = {
      {"char", ScalarType::kI8},    {"int8", ScalarType::kI8},     {"uchar", ScalarType::kU8},
      {"uint8", ScalarType::kU8},   {"short", ScalarType::kI16},   {"int16", ScalarType::kI16},
      {"ushort", ScalarType::kU16}, {"uint16", ScalarType::kU16},  {"int", ScalarType::kI32},
      {"int32", ScalarType::kI32},  {"uint", ScalarType::kU32},    {"uint32", ScalarType::kU32},
      {"float", ScalarType::kF32},  {"float32", ScalarType::kF32}, {"double", ScalarType::kF64},
      {"float64", ScalarType::kF64}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) fail_at(path, line, "unknown property type '" + std::string(name) + "'");
  return it->second;
}

struct PlyHeader {
  bool binary = false;
  std::size_t vertices = 0;
  Layout layout;
  std::size_t data_offset = 0, data_line = 0;
};

PlyHeader parse_header(const std::string& path, const std::string& bytes) {
  PlyHeader h;
  std::size_t pos = 0, line = 0;
  bool magic = false, format = false, ended = false;
  std::string element;  // current element name
  bool seen_vertex = false;
  while (pos < bytes.size() && !ended) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    const auto tokens = detail::split(std::string_view(bytes.data() + pos, end - pos));
    pos = end + 1;
    ++line;
    if (line == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply") fail(path, "not a PLY file (first line is not 'ply')");
      magic = true;
      continue;
    }
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "end_header") {
      ended = true;
    } else if (tokens[0] == "format" && tokens.size() == 3) {
      if (tokens[1] == "binary_big_endian") fail_at(path, line, "binary_big_endian PLY is unsupported");
      if (tokens[1] != "ascii" && tokens[1] != "binary_little_endian")
        fail_at(path, line, "unknown format '" + std::string(tokens[1]) + "'");
      h.binary = tokens[1] == "binary_little_endian";
      format = true;
    } else if (tokens[0] == "element" && tokens.size() == 3) {
      element = std::string(tokens[1]);
      if (element == "vertex") {
        if (seen_vertex) fail_at(path, line, "more than one element vertex");
        h.vertices = detail::parse_count(path, line, tokens[2]);
        seen_vertex = true;
      } else if (!seen_vertex) {
        fail_at(path, line, "unsupported: element '" + element + "' before element vertex");
      }
    } else if (tokens[0] == "property") {
      if (element.empty()) fail_at(path, line, "property before any element");
      if (element != "vertex") continue;
      if (tokens.size() >= 2 && tokens[1] == "list")
        fail_at(path, line, "list properties in vertex are unsupported");
      if (tokens.size() != 3) fail_at(path, line, "expected 'property TYPE NAME'");
      h.layout.add(std::string(tokens[2]), ply_type(path, line, tokens[1]));
    } else {
      fail_at(path, line, "unknown header line");
    }
  }
  if (!magic || !ended) fail(path, "PLY header has no end_header");
  if (!format) fail(path, "PLY header has no format line");
  if (!seen_vertex) fail(path, "PLY file has no element vertex");
  if (!h.layout.find({"x"}) || !h.layout.find({"y"}) || !h.layout.find({"z"}))
    fail(path, "vertex needs properties x y z");
  h.data_offset = std::min(pos, bytes.size());
  h.data_line = line + 1;
  // The data must hold the vertices before anything is allocated for them: a binary record is
  // `stride` bytes, an ascii line at least one character and a separator per value.
  const std::size_t per_vertex = h.binary ? h.layout.stride : 2 * h.layout.columns;
  const std::size_t available = bytes.size() - h.data_offset;
  if (per_vertex != 0 && h.vertices > (available + (h.binary ? 0 : 1)) / per_vertex)
    fail(path, "truncated: " + std::to_string(h.vertices) + " vertices need " +
                   (h.binary ? "" : "at least ") + std::to_string(per_vertex) + " data bytes each, found " +
                   std::to_string(available) + " bytes in all");
  return h;
}

/// A value cast to T, clamped to T's range (a direct cast of an out-of-range value is undefined).
template <class T>
T clamped(double v) {
  if (!(v == v)) return T{};
  const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  return static_cast<T>(std::clamp(v, lo, hi));
}
}  // namespace

PlyCloud read_ply(const std::string& path) { return parse_ply(read_file(path), path); }

PlyCloud parse_ply(const std::string& bytes, const std::string& path) {
  const PlyHeader h = parse_header(path, bytes);
  const Field fx = *h.layout.find({"x"}), fy = *h.layout.find({"y"}), fz = *h.layout.find({"z"});
  const auto fi = h.layout.find({"intensity"});
  const auto fr = h.layout.find({"red"}), fg = h.layout.find({"green"}), fb = h.layout.find({"blue"});
  const auto fl = h.layout.find({"label"});
  const bool with_rgb = fr && fg && fb;
  PlyCloud out;
  out.cloud.xyz.resize(h.vertices);
  if (fi) out.cloud.intensity.resize(h.vertices);
  if (with_rgb) out.rgb.resize(h.vertices);
  if (fl) out.label.resize(h.vertices);
  std::vector<double> values;
  auto get = [&](const Field& f, const char* record) {
    return h.binary ? detail::load_scalar(f.type, record + f.offset) : values[f.column];
  };
  std::size_t pos = h.data_offset, line = h.data_line;
  for (std::size_t i = 0; i < h.vertices; ++i, ++line) {
    const char* record = bytes.data() + pos;
    if (h.binary) {
      pos += h.layout.stride;
    } else {
      if (pos >= bytes.size())
        fail(path, "truncated: " + std::to_string(h.vertices) + " vertices declared, " + std::to_string(i) +
                       " found");
      std::size_t end = bytes.find('\n', pos);
      if (end == std::string::npos) end = bytes.size();
      std::string error;
      if (!detail::parse_doubles(std::string_view(bytes.data() + pos, end - pos), values, error, true))
        fail_at(path, line, error);
      if (values.size() != h.layout.columns)
        fail_at(
            path, line,
            "expected " + std::to_string(h.layout.columns) + " values, got " + std::to_string(values.size()));
      pos = end + 1;
    }
    const Vec3 p(get(fx, record), get(fy, record), get(fz, record));
    if (!p.allFinite()) fail(path, "vertex " + std::to_string(i) + " has a NaN or Inf coordinate");
    out.cloud.xyz[i] = p;
    if (fi) out.cloud.intensity[i] = clamped<float>(get(*fi, record));
    if (with_rgb)
      out.rgb[i] = {clamped<std::uint8_t>(get(*fr, record)), clamped<std::uint8_t>(get(*fg, record)),
                    clamped<std::uint8_t>(get(*fb, record))};
    if (fl) out.label[i] = clamped<float>(get(*fl, record));
  }
  return out;
}

void write_ply(const std::string& path, const PointCloud& cloud, Encoding encoding,
               const std::vector<Rgb>& rgb, const std::vector<float>& label) {
  const std::size_t n = cloud.size();
  if (!rgb.empty() && rgb.size() != n)
    fail(path,
         "cannot write " + std::to_string(rgb.size()) + " colours for " + std::to_string(n) + " points");
  if (!label.empty() && label.size() != n)
    fail(path,
         "cannot write " + std::to_string(label.size()) + " labels for " + std::to_string(n) + " points");
  const bool with_i = cloud.has_intensity(), binary = encoding == Encoding::kBinary;
  write_atomic(path, [&](std::ostream& out) {
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\ncomment written by dloam\n"
        << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n"
        << (with_i ? "property float intensity\n" : "")
        << (rgb.empty() ? "" : "property uchar red\nproperty uchar green\nproperty uchar blue\n")
        << (label.empty() ? "" : "property float label\n") << "end_header\n";
    std::string record;
    char buf[24];
    auto put_float = [&](float v) {
      if (binary) {
        record.append(reinterpret_cast<const char*>(&v), 4);
      } else {
        std::snprintf(buf, sizeof(buf), "%.9g ", static_cast<double>(v));
        record += buf;
      }
    };
    for (std::size_t i = 0; i < n; ++i) {
      record.clear();
      for (int a = 0; a < 3; ++a) put_float(static_cast<float>(cloud.xyz[i][a]));
      if (with_i) put_float(cloud.intensity[i]);
      if (!rgb.empty()) {
        for (const auto c : rgb[i]) {
          if (binary) {
            record.push_back(static_cast<char>(c));
          } else {
            record += std::to_string(c) + ' ';
          }
        }
      }
      if (!label.empty()) put_float(label[i]);
      if (!binary) record.back() = '\n';
      out.write(record.data(), static_cast<std::streamsize>(record.size()));
    }
  });
}

}  // namespace dloam::io
