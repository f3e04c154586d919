// PCD and PLY: round trips (ascii + binary), foreign layouts, and bad-input cases.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/ply.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using namespace dloam::io;
using dloam::test::input_error_of;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;

namespace {
PointCloud sweep(std::size_t n, bool with_time) {
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = static_cast<double>(i) / static_cast<double>(n);
    c.xyz.emplace_back(20.0 * std::cos(6.2 * f), -20.0 * std::sin(6.2 * f),
                       0.123456789 * static_cast<double>(i));
    c.intensity.push_back(static_cast<float>(f));
    if (with_time) c.time.push_back(static_cast<float>(f));
  }
  return c;
}

void expect_same(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.has_intensity(), b.has_intensity());
  ASSERT_EQ(a.has_time(), b.has_time());
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(static_cast<float>(a.xyz[i][k]), static_cast<float>(b.xyz[i][k]));
    if (a.has_intensity()) {
      EXPECT_EQ(a.intensity[i], b.intensity[i]);
    }
    if (a.has_time()) {
      EXPECT_EQ(a.time[i], b.time[i]);
    }
  }
}

template <class T>
void append(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
}  // namespace

TEST(Pcd, AsciiAndBinaryRoundTripsAreExactInFloat32) {
  TempDir dir;
  for (const bool with_time : {false, true}) {
    const auto cloud = sweep(2000, with_time);
    write_pcd(dir.file("a.pcd"), cloud, Encoding::kAscii);
    write_pcd(dir.file("b.pcd"), cloud, Encoding::kBinary);
    expect_same(read_pcd(dir.file("a.pcd")), cloud);
    expect_same(read_pcd(dir.file("b.pcd")), cloud);
  }
  PointCloud bare = sweep(10, false);
  bare.intensity.clear();
  write_pcd(dir.file("bare.pcd"), bare);
  EXPECT_FALSE(read_pcd(dir.file("bare.pcd")).has_intensity());
}

TEST(Pcd, ReadsForeignBinaryLayoutAndRescalesTimes) {
  // Ouster-like: double x, uint16 ring, float[3] normal, float y z, uint32 t in nanoseconds.
  TempDir dir;
  std::string pcd =
      "VERSION .7\nFIELDS x ring normal y z intensity t\nSIZE 8 2 4 4 4 4 4\nTYPE F U F F F F U\n"
      "COUNT 1 1 3 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA binary\n";
  const std::uint32_t t_ns[3] = {0, 50000000, 100000000};
  for (int i = 0; i < 3; ++i) {
    append(pcd, 1.5 * i);
    append(pcd, static_cast<std::uint16_t>(i));
    for (int k = 0; k < 3; ++k) append(pcd, std::nanf(""));  // NaN outside x y z is fine
    append(pcd, 2.0f + static_cast<float>(i));
    append(pcd, -1.0f);
    append(pcd, 7.0f);
    append(pcd, t_ns[i]);
  }
  write_text(dir.file("ouster.pcd"), pcd);
  const auto c = read_pcd(dir.file("ouster.pcd"));
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.xyz[2], Vec3(3.0, 4.0, -1.0));
  EXPECT_EQ(c.intensity[1], 7.0f);
  ASSERT_TRUE(c.has_time());
  EXPECT_EQ(c.time[0], 0.0f);
  EXPECT_NEAR(c.time[1], 0.5, 1e-6);
  EXPECT_LT(c.time[2], 1.0f);
  EXPECT_GT(c.time[2], 0.999f);
}

TEST(Pcd, RejectsBadInputNamingTheFile) {
  TempDir dir;
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  write_text(dir.file("compressed.pcd"), head + "DATA binary_compressed\n");
  const auto msg = input_error_of([&] { read_pcd(dir.file("compressed.pcd")); });
  EXPECT_THAT(msg, HasSubstr("compressed.pcd"));
  EXPECT_THAT(msg, HasSubstr("unsupported"));

  write_text(dir.file("short.pcd"), head + "DATA binary\n" + std::string(20, '\0'));
  EXPECT_THAT(input_error_of([&] { read_pcd(dir.file("short.pcd")); }), HasSubstr("short.pcd"));

  // A NaN/Inf coordinate is a no-return point: dropped (and counted); none finite is an error.
  write_text(dir.file("nan.pcd"), head + "DATA ascii\n1 2 3\n4 nan 6\n");
  ScanInfo info;
  EXPECT_EQ(read_pcd(dir.file("nan.pcd"), &info).size(), 1u);
  EXPECT_EQ(info.dropped(), 1u);
  write_text(dir.file("inf.pcd"), head + "DATA ascii\ninf 2 3\n4 5 nan\n");
  const auto inf_msg = input_error_of([&] { read_pcd(dir.file("inf.pcd")); });
  EXPECT_THAT(inf_msg, HasSubstr("inf.pcd"));
  EXPECT_THAT(inf_msg, HasSubstr("no point with finite coordinates"));

  write_text(dir.file("fewlines.pcd"), head + "DATA ascii\n1 2 3\n");
  EXPECT_THAT(input_error_of([&] { read_pcd(dir.file("fewlines.pcd")); }), HasSubstr("fewlines.pcd"));

  write_text(dir.file("noxyz.pcd"), "FIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 1\nWIDTH 1\nDATA ascii\n1 2\n");
  EXPECT_THAT(input_error_of([&] { read_pcd(dir.file("noxyz.pcd")); }), HasSubstr("x y z"));

  write_text(dir.file("empty.pcd"), "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nPOINTS 0\nDATA ascii\n");
  EXPECT_THAT(input_error_of([&] { read_pcd(dir.file("empty.pcd")); }), HasSubstr("empty"));

  EXPECT_THAT(input_error_of([&] { read_pcd(dir.file("missing.pcd")); }), HasSubstr("missing.pcd"));
}

TEST(Ply, RoundTripWithColoursAndLabels) {
  TempDir dir;
  const auto cloud = sweep(1500, false);
  std::vector<Rgb> rgb;
  std::vector<float> label;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    rgb.push_back({static_cast<std::uint8_t>(i % 256), 0, 255});
    label.push_back(static_cast<float>(i % 260));
  }
  for (const auto enc : {Encoding::kAscii, Encoding::kBinary}) {
    write_ply(dir.file("map.ply"), cloud, enc, rgb, label);
    const auto back = read_ply(dir.file("map.ply"));
    expect_same(back.cloud, cloud);
    EXPECT_EQ(back.rgb, rgb);
    EXPECT_EQ(back.label, label);
  }
  PointCloud xyz_only = cloud;
  xyz_only.intensity.clear();
  write_ply(dir.file("plain.ply"), xyz_only);
  const auto plain = read_ply(dir.file("plain.ply"));
  expect_same(plain.cloud, xyz_only);
  EXPECT_TRUE(plain.rgb.empty());
  EXPECT_TRUE(plain.label.empty());
  EXPECT_THAT(input_error_of([&] {
                write_ply(dir.file("bad.ply"), cloud, Encoding::kBinary, {{1, 2, 3}});
              }),
              HasSubstr("bad.ply"));
}

TEST(Ply, RejectsBadInputNamingTheFile) {
  TempDir dir;
  const std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  write_text(dir.file("trunc.ply"), head + std::string(13, '\0'));
  EXPECT_THAT(input_error_of([&] { read_ply(dir.file("trunc.ply")); }), HasSubstr("trunc.ply"));
  std::string big = head;
  big.replace(big.find("little"), 6, "big");
  write_text(dir.file("big.ply"), big + std::string(24, '\0'));
  EXPECT_THAT(input_error_of([&] { read_ply(dir.file("big.ply")); }), HasSubstr("unsupported"));
  write_text(dir.file("notply.ply"), "solid cube\n");
  EXPECT_THAT(input_error_of([&] { read_ply(dir.file("notply.ply")); }), HasSubstr("notply.ply"));
  write_text(dir.file("nan.ply"),
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
             "property float z\nend_header\n0 0 0\n0 nan 0\n");
  EXPECT_THAT(input_error_of([&] { read_ply(dir.file("nan.ply")); }), HasSubstr("vertex 1 "));
}

TEST(Formats, EveryTruncationIsAnInputErrorOrAValidPrefix) {
  TempDir dir;
  const auto cloud = sweep(6, true);  // small: one file per truncation length
  struct Case {
    std::string name;
    std::function<void(const std::string&)> write, read;
  };
  const std::vector<Case> cases = {
      {"a.pcd", [&](const std::string& p) { write_pcd(p, cloud, Encoding::kAscii); },
       [](const std::string& p) { read_pcd(p); }},
      {"b.pcd", [&](const std::string& p) { write_pcd(p, cloud, Encoding::kBinary); },
       [](const std::string& p) { read_pcd(p); }},
      {"a.ply",
       [&](const std::string& p) { write_ply(p, cloud, Encoding::kAscii, {}, std::vector<float>(6, 1.0f)); },
       [](const std::string& p) { read_ply(p); }},
      {"b.ply",
       [&](const std::string& p) { write_ply(p, cloud, Encoding::kBinary, {}, std::vector<float>(6, 1.0f)); },
       [](const std::string& p) { read_ply(p); }},
  };
  for (const auto& c : cases) {
    const std::string full = dir.file(c.name);
    c.write(full);
    const std::string bytes = read_file(full);
    std::size_t errors = 0;
    for (std::size_t len = 0; len < bytes.size(); ++len) {
      const std::string cut = dir.file("cut-" + c.name);
      write_text(cut, bytes.substr(0, len));
      try {
        c.read(cut);
      } catch (const InputError& e) {
        ++errors;
        EXPECT_THAT(e.what(), HasSubstr("cut-" + c.name));
      }
    }
    // Ascii files cut inside the last number still parse; everything shorter must fail.
    EXPECT_GE(errors + 20, bytes.size()) << c.name;
  }
}
