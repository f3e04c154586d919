// sensor_msgs/msg/PointCloud2 in CDR: the encoder and decoder agree; driver field layouts (time
// fields in their units), big-endian data and messages, damaged messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "dloam/io/cdr.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using dloam::test::input_error_of;
using ::testing::HasSubstr;

PointCloud sample_cloud(std::size_t n, bool with_time) {
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.xyz.emplace_back(0.5 * static_cast<double>(i), -1.25, 3.0 + 0.25 * static_cast<double>(i % 7));
    c.intensity.push_back(static_cast<float>(i % 100));
    if (with_time) c.time.push_back(static_cast<float>(i) / static_cast<float>(n));
  }
  return c;
}

TEST(PointCloud2Cdr, EncodedCloudsDecodeToTheSamePoints) {
  const PointCloud cloud = sample_cloud(1000, true);
  const auto data = io::encode_pointcloud2(cloud, 1317000000.25, "velodyne");
  double stamp = 0.0;
  const io::ConvertedCloud back = io::read_pointcloud2(data.data(), data.size(), "m", &stamp);
  EXPECT_DOUBLE_EQ(stamp, 1317000000.25);
  ASSERT_EQ(back.cloud.size(), cloud.size());
  ASSERT_TRUE(back.cloud.has_intensity());
  ASSERT_TRUE(back.cloud.has_time());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(back.cloud.xyz[i], cloud.xyz[i]);
    EXPECT_EQ(back.cloud.intensity[i], cloud.intensity[i]);
    EXPECT_EQ(back.cloud.time[i], cloud.time[i]);  // fractions kept as they are
  }
  const io::PointCloud2Message m = io::parse_pointcloud2(data.data(), data.size(), "m");
  EXPECT_EQ(m.frame_id, "velodyne");
  EXPECT_EQ(m.view.point_step, 20u);
  EXPECT_EQ(m.view.fields.size(), 5u);
}

/// A hand-made message: `fields` (name, offset, datatype), point_step, the point bytes, byte
/// order of the CDR stream and of the point data.
std::vector<std::uint8_t> make_message(const std::vector<io::CloudField>& fields, std::uint32_t step,
                                       std::uint32_t n, const std::vector<std::uint8_t>& points, bool big_cdr,
                                       bool big_points) {
  io::CdrWriter w;
  w.i32(10);
  w.u32(0);
  w.string("lidar");
  w.u32(1);
  w.u32(n);
  w.u32(static_cast<std::uint32_t>(fields.size()));
  for (const auto& f : fields) {
    w.string(f.name);
    w.u32(f.offset);
    w.u8(f.datatype);
    w.u32(1);
  }
  w.boolean(big_points);
  w.u32(step);
  w.u32(step * n);
  w.byte_sequence(points.data(), points.size());
  w.boolean(true);
  auto d = w.take();
  if (!big_cdr) return d;
  // Re-encode big-endian by reading the little-endian stream field by field.
  io::CdrReader r(d.data(), d.size(), "le");
  std::vector<std::uint8_t> be = {0x00, 0x00, 0x00, 0x00};
  auto align = [&](std::size_t a) {
    while ((be.size() - 4) % a) be.push_back(0);
  };
  auto u32 = [&](std::uint32_t v) {
    align(4);
    for (int s = 24; s >= 0; s -= 8) be.push_back(static_cast<std::uint8_t>(v >> s));
  };
  auto str = [&](const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size() + 1));
    be.insert(be.end(), s.begin(), s.end());
    be.push_back(0);
  };
  u32(static_cast<std::uint32_t>(r.i32("sec")));
  u32(r.u32("nsec"));
  str(r.string("frame"));
  u32(r.u32("h"));
  u32(r.u32("w"));
  const std::uint32_t nf = r.u32("nf");
  u32(nf);
  for (std::uint32_t k = 0; k < nf; ++k) {
    str(r.string("name"));
    u32(r.u32("off"));
    be.push_back(r.u8("type"));
    u32(r.u32("count"));
  }
  be.push_back(r.u8("big"));
  u32(r.u32("step"));
  u32(r.u32("row"));
  std::size_t len = 0;
  const std::uint8_t* p = r.byte_sequence(len, "data");
  u32(static_cast<std::uint32_t>(len));
  be.insert(be.end(), p, p + len);
  be.push_back(r.u8("dense"));
  return be;
}

template <class T>
void put(std::vector<std::uint8_t>& b, std::size_t at, T v, bool big) {
  std::uint8_t raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) b[at + i] = raw[big ? sizeof(T) - 1 - i : i];
}

TEST(PointCloud2Cdr, DriverLayoutsInBothByteOrders) {
  using T = io::PointFieldType;
  auto u8 = [](T t) { return static_cast<std::uint8_t>(t); };
  const std::uint32_t n = 50;
  struct Layout {
    const char* name;
    std::vector<io::CloudField> fields;
    std::uint32_t step;
  };
  const std::vector<Layout> layouts = {
      {"velodyne",
       {{"x", 0, u8(T::kFloat32)},
        {"y", 4, u8(T::kFloat32)},
        {"z", 8, u8(T::kFloat32)},
        {"intensity", 12, u8(T::kFloat32)},
        {"ring", 16, u8(T::kUint16)},
        {"time", 18, u8(T::kFloat32)}},
       22},
      {"ouster",
       {{"x", 0, u8(T::kFloat32)},
        {"y", 4, u8(T::kFloat32)},
        {"z", 8, u8(T::kFloat32)},
        {"t", 16, u8(T::kUint32)},
        {"intensity", 20, u8(T::kUint16)}},
       24},
      {"hesai",
       {{"x", 0, u8(T::kFloat64)},
        {"y", 8, u8(T::kFloat64)},
        {"z", 16, u8(T::kFloat64)},
        {"intensity", 24, u8(T::kUint8)},
        {"timestamp", 28, u8(T::kFloat64)}},
       36},
      {"nebula",
       {{"x", 0, u8(T::kFloat32)},
        {"y", 4, u8(T::kFloat32)},
        {"z", 8, u8(T::kFloat32)},
        {"intensity", 12, u8(T::kUint8)},
        {"time_stamp", 16, u8(T::kUint32)}},
       20},
  };
  for (const auto& l : layouts) {
    for (const bool big : {false, true}) {
      std::vector<std::uint8_t> pts(static_cast<std::size_t>(l.step) * n, 0);
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t base = static_cast<std::size_t>(i) * l.step;
        for (const auto& f : l.fields) {
          const std::string name = f.name;
          const double coord = name == "x" ? i : name == "y" ? -2.0 * i : 0.5;
          const double frac = static_cast<double>(i) / n;
          if (name == "x" || name == "y" || name == "z") {
            if (f.datatype == u8(T::kFloat64))
              put(pts, base + f.offset, coord, big);
            else
              put(pts, base + f.offset, static_cast<float>(coord), big);
          } else if (name == "intensity") {
            if (f.datatype == u8(T::kFloat32)) put(pts, base + f.offset, static_cast<float>(i), big);
            if (f.datatype == u8(T::kUint16)) put(pts, base + f.offset, static_cast<std::uint16_t>(i), big);
            if (f.datatype == u8(T::kUint8)) pts[base + f.offset] = static_cast<std::uint8_t>(i);
          } else if (name == "time") {
            put(pts, base + f.offset, static_cast<float>(0.1 * frac), big);
          } else if (name == "t" || name == "time_stamp") {
            put(pts, base + f.offset, static_cast<std::uint32_t>(std::llround(1e8 * frac)), big);
          } else if (name == "timestamp") {
            put(pts, base + f.offset, 1.7e9 + 0.1 * frac, big);
          }
        }
      }
      const auto msg = make_message(l.fields, l.step, n, pts, big, big);
      const io::ConvertedCloud c = io::read_pointcloud2(msg.data(), msg.size(), l.name);
      ASSERT_EQ(c.cloud.size(), n) << l.name << (big ? " big-endian" : "");
      ASSERT_TRUE(c.cloud.has_intensity()) << l.name;
      ASSERT_TRUE(c.cloud.has_time()) << l.name;
      for (std::uint32_t i = 0; i < n; ++i) {
        EXPECT_EQ(c.cloud.xyz[i].x(), static_cast<double>(i)) << l.name;
        EXPECT_EQ(c.cloud.xyz[i].y(), -2.0 * i) << l.name;
        EXPECT_EQ(c.cloud.intensity[i], static_cast<float>(i)) << l.name;
        EXPECT_NEAR(c.cloud.time[i], static_cast<double>(i) / (n - 1), 1e-5) << l.name;  // rescaled to [0, 1)
      }
    }
  }
}

TEST(PointCloud2Cdr, DamagedMessagesAreInputErrorsNamingTheMessage) {
  const PointCloud cloud = sample_cloud(100, false);
  auto data = io::encode_pointcloud2(cloud, 5.0, "lidar");
  const std::string where = "drive.mcap: topic /points, message 7";
  auto cut = data;
  cut.resize(cut.size() - 500);
  EXPECT_THAT(input_error_of([&] { io::read_pointcloud2(cut.data(), cut.size(), where); }),
              HasSubstr(where + ": message shorter than its fields (data"));
  auto header_only = data;
  header_only.resize(30);
  EXPECT_THAT(input_error_of([&] { io::read_pointcloud2(header_only.data(), header_only.size(), where); }),
              HasSubstr(where + ": message shorter than its fields"));
  // A row_step larger than the data announces: truncated cloud.
  io::PointCloud2Message m = io::parse_pointcloud2(data.data(), data.size(), where);
  m.view.row_step += 4;
  EXPECT_THAT(input_error_of([&] { io::convert_cloud(m.view, where); }), HasSubstr(where + ": truncated"));
  m = io::parse_pointcloud2(data.data(), data.size(), where);
  m.view.fields.erase(m.view.fields.begin());
  EXPECT_THAT(input_error_of([&] { io::convert_cloud(m.view, where); }),
              HasSubstr(where + ": has no 'x' field"));
}

}  // namespace
}  // namespace dloam
