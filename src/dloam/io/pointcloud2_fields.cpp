// sensor_msgs/PointCloud2 layout -> dloam::PointCloud (see pointcloud2_fields.hpp).
#include "dloam/io/pointcloud2_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "dloam/io/bytes.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace {
[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

const char* datatype_name(std::uint8_t type) {
  static const char* names[] = {"unknown", "int8",   "uint8",   "int16",  "uint16",
                                "int32",   "uint32", "float32", "float64"};
  return type <= 8 ? names[type] : "unknown";
}

std::size_t datatype_size(std::uint8_t type) {
  switch (static_cast<PointFieldType>(type)) {
    case PointFieldType::kInt8:
    case PointFieldType::kUint8:
      return 1;
    case PointFieldType::kInt16:
    case PointFieldType::kUint16:
      return 2;
    case PointFieldType::kInt32:
    case PointFieldType::kUint32:
    case PointFieldType::kFloat32:
      return 4;
    case PointFieldType::kFloat64:
      return 8;
  }
  return 0;
}

struct Reader {
  std::uint8_t type;
  std::size_t offset;
  bool big;
  double scale;  ///< to seconds for times in nanoseconds
  [[nodiscard]] double get(const std::uint8_t* point) const {
    const std::uint8_t* p = point + offset;
    double v = 0.0;
    switch (static_cast<PointFieldType>(type)) {
      case PointFieldType::kInt8:
        v = static_cast<std::int8_t>(p[0]);
        break;
      case PointFieldType::kUint8:
        v = p[0];
        break;
      case PointFieldType::kInt16:
        v = detail::load_scalar_as<std::int16_t>(p, big);
        break;
      case PointFieldType::kUint16:
        v = detail::load_scalar_as<std::uint16_t>(p, big);
        break;
      case PointFieldType::kInt32:
        v = detail::load_scalar_as<std::int32_t>(p, big);
        break;
      case PointFieldType::kUint32:
        v = detail::load_scalar_as<std::uint32_t>(p, big);
        break;
      case PointFieldType::kFloat32:
        v = detail::load_scalar_as<float>(p, big);
        break;
      case PointFieldType::kFloat64:
        v = detail::load_scalar_as<double>(p, big);
        break;
    }
    return scale * v;
  }
};

std::string field_list(const CloudView& msg) {
  std::string names;
  for (const auto& f : msg.fields) names += (names.empty() ? "" : " ") + f.name;
  return names.empty() ? "none" : names;
}

/// The first field with one of `names`, checked: a known datatype, one of `allowed` when given,
/// inside the point record.
std::optional<Reader> find_field(const CloudView& msg, const std::string& where,
                                 std::initializer_list<const char*> names,
                                 std::initializer_list<PointFieldType> allowed = {}) {
  for (const char* name : names) {
    for (const auto& f : msg.fields) {
      if (f.name != name) continue;
      const std::size_t size = datatype_size(f.datatype);
      const bool ok =
          size > 0 && (allowed.size() == 0 || std::any_of(allowed.begin(), allowed.end(), [&](auto a) {
                         return static_cast<std::uint8_t>(a) == f.datatype;
                       }));
      if (!ok) {
        std::string expected;
        for (auto a : allowed)
          expected +=
              (expected.empty() ? "" : " or ") + std::string(datatype_name(static_cast<std::uint8_t>(a)));
        fail(where, "field '" + f.name + "' has datatype " + datatype_name(f.datatype) +
                        (expected.empty() ? " (unsupported)" : ", expected " + expected));
      }
      if (static_cast<std::size_t>(f.offset) + size > msg.point_step)
        fail(where, "field '" + f.name + "' at offset " + std::to_string(f.offset) + " lies outside the " +
                        std::to_string(msg.point_step) + "-byte point record");
      return Reader{f.datatype, f.offset, msg.is_bigendian, 1.0};
    }
  }
  return std::nullopt;
}

void check_layout(const CloudView& msg, const std::string& where) {
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  if (n == 0) fail(where, "empty cloud (0 points)");
  if (msg.point_step == 0) fail(where, "point_step 0 (a point record must hold x, y and z)");
  if (msg.row_step < static_cast<std::size_t>(msg.width) * msg.point_step)
    fail(where, "row_step " + std::to_string(msg.row_step) + " < width " + std::to_string(msg.width) +
                    " * point_step " + std::to_string(msg.point_step));
  const std::size_t need = static_cast<std::size_t>(msg.row_step) * msg.height;
  if (msg.size < need)
    fail(where, "truncated: " + std::to_string(msg.width) + " x " + std::to_string(msg.height) +
                    " points (row_step " + std::to_string(msg.row_step) + ") need " + std::to_string(need) +
                    " data bytes, found " + std::to_string(msg.size));
}
}  // namespace

ConvertedCloud convert_cloud(const CloudView& msg, const std::string& where) {
  check_layout(msg, where);
  const std::initializer_list<PointFieldType> xyz_types = {PointFieldType::kFloat32,
                                                           PointFieldType::kFloat64};
  std::optional<Reader> axis[3];
  const char* axis_names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    axis[a] = find_field(msg, where, {axis_names[a]}, xyz_types);
    if (!axis[a])
      fail(where, std::string("has no '") + axis_names[a] + "' field (fields: " + field_list(msg) + ")");
  }
  const auto intensity = find_field(msg, where, {"intensity"});
  auto time = find_field(msg, where, {"time", "t", "timestamp", "time_stamp"},
                         {PointFieldType::kFloat32, PointFieldType::kFloat64, PointFieldType::kUint32});
  if (time && time->type == static_cast<std::uint8_t>(PointFieldType::kUint32)) time->scale = 1e-9;  // ns
  ConvertedCloud out;
  PointCloud& cloud = out.cloud;
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  cloud.xyz.reserve(n);
  if (intensity) cloud.intensity.reserve(n);
  std::vector<double> times;
  if (time) times.reserve(n);
  for (std::size_t row = 0, i = 0; row < msg.height; ++row) {
    const std::uint8_t* record = msg.data + row * msg.row_step;
    for (std::size_t col = 0; col < msg.width; ++col, ++i, record += msg.point_step) {
      const Vec3 p(axis[0]->get(record), axis[1]->get(record), axis[2]->get(record));
      if (!p.allFinite()) {
        if (msg.is_dense)
          fail(where, "point " + std::to_string(i) + " has a NaN or Inf coordinate but the message is_dense");
        ++out.dropped;
        continue;
      }
      if (p.cwiseAbs().maxCoeff() > detail::kMaxPointDistance)
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
  if (time) cloud.time = to_sweep_fraction(times);
  return out;
}

}  // namespace dloam::io
