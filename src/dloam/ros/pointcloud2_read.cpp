// sensor_msgs/PointCloud2 -> dloam::PointCloud (see pointcloud2.hpp).
#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "dloam/io/fields.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/text_util.hpp"
#include "dloam/ros/pointcloud2.hpp"

namespace dloam::ros1 {

namespace {
using io::detail::ScalarType;
using sensor_msgs::PointField;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

const char* datatype_name(std::uint8_t type) {
  static const char* names[] = {"unknown", "int8",   "uint8",   "int16",  "uint16",
                                "int32",   "uint32", "float32", "float64"};
  return type <= PointField::FLOAT64 ? names[type] : "unknown";
}

std::optional<ScalarType> scalar_type(std::uint8_t type) {
  switch (type) {
    case PointField::INT8:
      return ScalarType::kI8;
    case PointField::UINT8:
      return ScalarType::kU8;
    case PointField::INT16:
      return ScalarType::kI16;
    case PointField::UINT16:
      return ScalarType::kU16;
    case PointField::INT32:
      return ScalarType::kI32;
    case PointField::UINT32:
      return ScalarType::kU32;
    case PointField::FLOAT32:
      return ScalarType::kF32;
    case PointField::FLOAT64:
      return ScalarType::kF64;
    default:
      return std::nullopt;
  }
}

struct Reader {
  ScalarType type;
  std::size_t offset;
  double scale;  ///< to seconds for times in nanoseconds
  [[nodiscard]] double get(const std::uint8_t* point) const {
    return scale * io::detail::load_scalar(type, reinterpret_cast<const char*>(point) + offset);
  }
};

std::string field_list(const sensor_msgs::PointCloud2& msg) {
  std::string names;
  for (const auto& f : msg.fields) names += (names.empty() ? "" : " ") + f.name;
  return names.empty() ? "none" : names;
}

/// The first field with one of `names`, checked: a known datatype, one of `allowed` when given,
/// inside the point record.
std::optional<Reader> find_field(const sensor_msgs::PointCloud2& msg, const std::string& where,
                                 std::initializer_list<const char*> names,
                                 std::initializer_list<std::uint8_t> allowed = {}) {
  for (const char* name : names) {
    for (const auto& f : msg.fields) {
      if (f.name != name) continue;
      const auto type = scalar_type(f.datatype);
      const bool ok = type && (allowed.size() == 0 ||
                               std::find(allowed.begin(), allowed.end(), f.datatype) != allowed.end());
      if (!ok) {
        std::string expected;
        for (auto a : allowed) expected += (expected.empty() ? "" : " or ") + std::string(datatype_name(a));
        fail(where, "field '" + f.name + "' has datatype " + datatype_name(f.datatype) +
                        (expected.empty() ? " (unsupported)" : ", expected " + expected));
      }
      if (f.offset + io::detail::scalar_size(*type) > msg.point_step)
        fail(where, "field '" + f.name + "' at offset " + std::to_string(f.offset) + " lies outside the " +
                        std::to_string(msg.point_step) + "-byte point record");
      return Reader{*type, f.offset, 1.0};
    }
  }
  return std::nullopt;
}

void check_layout(const sensor_msgs::PointCloud2& msg, const std::string& where) {
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  if (n == 0) fail(where, "empty cloud (0 points)");
  if (msg.is_bigendian) fail(where, "big-endian point data is unsupported");
  if (msg.row_step < static_cast<std::size_t>(msg.width) * msg.point_step)
    fail(where, "row_step " + std::to_string(msg.row_step) + " < width " + std::to_string(msg.width) +
                    " * point_step " + std::to_string(msg.point_step));
  const std::size_t need = static_cast<std::size_t>(msg.row_step) * msg.height;
  if (msg.data.size() < need)
    fail(where, "truncated: " + std::to_string(msg.width) + " x " + std::to_string(msg.height) +
                    " points (row_step " + std::to_string(msg.row_step) + ") need " + std::to_string(need) +
                    " data bytes, found " + std::to_string(msg.data.size()));
}
}  // namespace

ConvertedCloud from_pointcloud2(const sensor_msgs::PointCloud2& msg, const std::string& where) {
  check_layout(msg, where);
  const std::initializer_list<std::uint8_t> xyz_types = {PointField::FLOAT32, PointField::FLOAT64};
  Reader axis[3] = {Reader{ScalarType::kF32, 0, 1.0}, Reader{ScalarType::kF32, 0, 1.0},
                    Reader{ScalarType::kF32, 0, 1.0}};
  const char* axis_names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const auto r = find_field(msg, where, {axis_names[a]}, xyz_types);
    if (!r)
      fail(where, std::string("has no '") + axis_names[a] + "' field (fields: " + field_list(msg) + ")");
    axis[a] = *r;
  }
  const auto intensity = find_field(msg, where, {"intensity"});
  auto time = find_field(msg, where, {"time", "t", "timestamp"},
                         {PointField::FLOAT32, PointField::FLOAT64, PointField::UINT32});
  if (time && time->type == ScalarType::kU32) time->scale = 1e-9;  // Ouster: nanoseconds
  ConvertedCloud out;
  PointCloud& cloud = out.cloud;
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  cloud.xyz.reserve(n);
  std::vector<double> times;
  for (std::size_t row = 0, i = 0; row < msg.height; ++row) {
    const std::uint8_t* record = msg.data.data() + row * msg.row_step;
    for (std::size_t col = 0; col < msg.width; ++col, ++i, record += msg.point_step) {
      const Vec3 p(axis[0].get(record), axis[1].get(record), axis[2].get(record));
      if (!p.allFinite()) {
        if (msg.is_dense)
          fail(where, "point " + std::to_string(i) + " has a NaN or Inf coordinate but the message is_dense");
        ++out.dropped;
        continue;
      }
      if (p.cwiseAbs().maxCoeff() > io::detail::kMaxPointDistance)
        fail(where, "point " + std::to_string(i) + " is farther than 1e6 m from the sensor: no LiDAR return");
      cloud.xyz.push_back(p);
      if (intensity) {
        const double v = intensity->get(record);
        if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
          fail(where, "point " + std::to_string(i) + " has intensity " + std::to_string(v) +
                          " (not a finite float32)");
        cloud.intensity.push_back(static_cast<float>(v));
      }
      if (time) {
        const double t = time->get(record);
        if (!std::isfinite(t)) fail(where, "point " + std::to_string(i) + " has a NaN or Inf time");
        times.push_back(t);
      }
    }
  }
  if (cloud.empty()) fail(where, "no finite point (all " + std::to_string(n) + " are NaN/Inf)");
  if (time) cloud.time = io::to_sweep_fraction(times);
  return out;
}

}  // namespace dloam::ros1
