// sensor_msgs/msg/PointCloud2 in CDR (see pointcloud2_cdr.hpp). Layout:
//   std_msgs/Header header (builtin_interfaces/Time stamp, string frame_id), uint32 height,
//   uint32 width, PointField[] fields (string name, uint32 offset, uint8 datatype, uint32 count),
//   bool is_bigendian, uint32 point_step, uint32 row_step, uint8[] data, bool is_dense.
#include "dloam/io/pointcloud2_cdr.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "dloam/io/cdr.hpp"

namespace dloam::io {

PointCloud2Message parse_pointcloud2(const std::uint8_t* data, std::size_t size, const std::string& where) {
  CdrReader r(data, size, where);
  PointCloud2Message m;
  const std::int32_t sec = r.i32("header.stamp.sec");
  const std::uint32_t nsec = r.u32("header.stamp.nanosec");
  m.stamp = static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
  m.frame_id = r.string("header.frame_id");
  CloudView& v = m.view;
  v.height = r.u32("height");
  v.width = r.u32("width");
  const std::uint32_t n_fields = r.sequence_count(4 + 4 + 1 + 4, "fields");
  v.fields.reserve(n_fields);
  for (std::uint32_t k = 0; k < n_fields; ++k) {
    CloudField f;
    f.name = r.string("fields[].name");
    f.offset = r.u32("fields[].offset");
    f.datatype = r.u8("fields[].datatype");
    f.count = r.u32("fields[].count");
    v.fields.push_back(std::move(f));
  }
  v.is_bigendian = r.boolean("is_bigendian");
  v.point_step = r.u32("point_step");
  v.row_step = r.u32("row_step");
  v.data = r.byte_sequence(v.size, "data");
  v.is_dense = r.boolean("is_dense");
  return m;
}

ConvertedCloud read_pointcloud2(const std::uint8_t* data, std::size_t size, const std::string& where,
                                double* stamp) {
  const PointCloud2Message m = parse_pointcloud2(data, size, where);
  if (stamp) *stamp = m.stamp;
  return convert_cloud(m.view, where);
}

std::vector<std::uint8_t> encode_pointcloud2(const PointCloud& cloud, double stamp,
                                             const std::string& frame_id) {
  const bool with_i = cloud.has_intensity(), with_t = cloud.has_time();
  std::vector<std::pair<const char*, std::uint32_t>> fields = {{"x", 0}, {"y", 4}, {"z", 8}};
  std::uint32_t step = 12;
  if (with_i) fields.emplace_back("intensity", std::exchange(step, step + 4));
  if (with_t) fields.emplace_back("time", std::exchange(step, step + 4));
  CdrWriter w;
  const double sec = std::floor(stamp);
  w.i32(static_cast<std::int32_t>(sec));
  w.u32(static_cast<std::uint32_t>(std::min(999999999.0, std::round((stamp - sec) * 1e9))));
  w.string(frame_id);
  w.u32(1);
  w.u32(static_cast<std::uint32_t>(cloud.size()));
  w.u32(static_cast<std::uint32_t>(fields.size()));
  for (const auto& [name, offset] : fields) {
    w.string(name);
    w.u32(offset);
    w.u8(static_cast<std::uint8_t>(PointFieldType::kFloat32));
    w.u32(1);
  }
  w.boolean(false);
  w.u32(step);
  w.u32(step * static_cast<std::uint32_t>(cloud.size()));
  std::vector<std::uint8_t> points(static_cast<std::size_t>(step) * cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    float v[5];
    std::size_t k = 0;
    for (int a = 0; a < 3; ++a) v[k++] = static_cast<float>(cloud.xyz[i][a]);
    if (with_i) v[k++] = cloud.intensity[i];
    if (with_t) v[k++] = cloud.time[i];
    std::memcpy(points.data() + i * step, v, k * sizeof(float));
  }
  w.byte_sequence(points.data(), points.size());
  w.boolean(true);
  return w.take();
}

const std::string& pointcloud2_definition() {
  static const std::string text =
      "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\nbool is_bigendian\n"
      "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n"
      "================================================================================\n"
      "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n"
      "================================================================================\n"
      "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
      "================================================================================\n"
      "MSG: sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\n"
      "uint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\n"
      "uint8 datatype\nuint32 count\n";
  return text;
}

}  // namespace dloam::io
