// MCAP: files written by McapWriter in every layout (chunked or not; none / lz4 / zstd; with and
// without message indexes and summary) read back through io::Bag in time order; damaged files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dloam/io/bag.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "test_io_util.hpp"

namespace dloam {
namespace {

using namespace dloam::test;  // NOLINT: the test helpers
using ::testing::HasSubstr;
using Bytes = std::vector<std::uint8_t>;

Bytes message(std::size_t n, unsigned seed) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>((seed * 31 + i) % 253);
  return b;
}

Bytes read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_all(const std::string& path, const Bytes& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
}

/// 40 messages on /points (written out of time order) and 15 on /packets, small chunks.
void write_sample(const std::string& path, const io::McapWriterOptions& options) {
  io::McapWriter w(path, options);
  const auto cloud = w.add_schema("sensor_msgs/msg/PointCloud2", "ros2msg", "uint32 height\n");
  const auto packets = w.add_schema("velodyne_msgs/msg/VelodyneScan", "ros2msg", "");
  const auto a = w.add_channel("/points", "cdr", cloud, {{"offered_qos_profiles", ""}});
  const auto b = w.add_channel("/packets", "cdr", packets);
  for (unsigned k = 0; k < 40; ++k) {
    const unsigned t = k % 2 ? k - 1 : k + 1;  // pairs swapped
    const Bytes m = message(3000 + 100 * t, t);
    w.write(a, 1'000'000'000ull + t * 100'000'000ull, m.data(), m.size());
    if (k % 3 == 0) {
      const Bytes p = message(1206, 1000 + k);
      w.write(b, 1'000'000'000ull + k * 100'000'000ull + 1, p.data(), p.size());
    }
  }
  w.close();
}

void expect_sample(const std::string& path, const std::string& label) {
  const io::Bag bag(path);
  ASSERT_EQ(bag.topics().size(), 2u) << label;
  const io::BagTopic* points = bag.find_topic("/points");
  ASSERT_NE(points, nullptr) << label;
  EXPECT_EQ(points->type, "sensor_msgs/msg/PointCloud2") << label;
  EXPECT_EQ(points->encoding, "cdr") << label;
  EXPECT_EQ(points->messages, 40u) << label;
  ASSERT_EQ(bag.message_count("/points"), 40u) << label;
  for (unsigned k = 0; k < 40; ++k) {
    EXPECT_EQ(bag.message_time_ns("/points", k), 1'000'000'000ll + k * 100'000'000ll) << label;
    EXPECT_EQ(bag.read("/points", k), message(3000 + 100 * k, k)) << label << " message " << k;
  }
  ASSERT_EQ(bag.message_count("/packets"), 14u) << label;
  EXPECT_EQ(bag.read("/packets", 13), message(1206, 1039)) << label;
}

TEST(Mcap, EveryLayoutTheWriterProducesReadsBackInTimeOrder) {
  TempDir dir;
  struct Layout {
    const char* name;
    io::McapWriterOptions options;
  };
  std::vector<Layout> layouts;
  for (const char* compression : {"", "lz4", "zstd"}) {
    io::McapWriterOptions o;
    o.compression = compression;
    o.chunk_size = 20000;
    layouts.push_back({compression, o});
  }
  io::McapWriterOptions unchunked;
  unchunked.chunked = false;
  layouts.push_back({"unchunked", unchunked});
  io::McapWriterOptions unchunked_bare = unchunked;
  unchunked_bare.summary = false;
  layouts.push_back({"unchunked, no summary", unchunked_bare});
  io::McapWriterOptions no_index;
  no_index.chunk_size = 20000;
  no_index.message_indexes = false;
  layouts.push_back({"chunks without message indexes", no_index});
  io::McapWriterOptions no_summary;
  no_summary.chunk_size = 20000;
  no_summary.compression = "lz4";
  no_summary.summary = false;
  layouts.push_back({"chunked, no summary", no_summary});
  for (const auto& l : layouts) {
    const std::string path = dir.file(std::string("sample-") + std::to_string(&l - layouts.data()) + ".mcap");
    write_sample(path, l.options);
    EXPECT_FALSE(std::filesystem::exists(path + ".part"));
    expect_sample(path, l.name);
  }
  EXPECT_THAT(io::Bag(dir.file("sample-2.mcap")).describe(), HasSubstr("MCAP (chunked, zstd, indexed)"));
  EXPECT_THAT(io::Bag(dir.file("sample-6.mcap")).describe(), HasSubstr("linear scan"));
  // In memory, as a fuzzer calls it.
  const auto file = io::bag_detail::open_mcap_memory(read_all(dir.file("sample-1.mcap")), "mem.mcap");
  EXPECT_EQ(file->index("/points").size(), 40u);
}

TEST(Mcap, UnfinishedWriterLeavesNoFile) {
  TempDir dir;
  const std::string path = dir.file("gone.mcap");
  {
    io::McapWriter w(path);
    const auto c = w.add_channel("/x", "cdr", 0);
    const Bytes m = message(10, 1);
    w.write(c, 1, m.data(), m.size());
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
}

TEST(Mcap, DamagedFilesAreInputErrorsNamingTheFileAndTheProblem) {
  TempDir dir;
  io::McapWriterOptions lz4;
  lz4.compression = "lz4";
  lz4.chunk_size = 20000;
  const std::string good = dir.file("good.mcap");
  write_sample(good, lz4);
  const Bytes bytes = read_all(good);

  // Unknown compression, found in the chunk index (summary) or in the chunk itself (linear scan).
  Bytes renamed = bytes;
  const std::string from = std::string("\x03\0\0\0lz4", 7), to = std::string("\x03\0\0\0br9", 7);
  std::size_t replaced = 0;
  for (std::size_t i = 0; i + from.size() <= renamed.size(); ++i)
    if (std::equal(from.begin(), from.end(), renamed.begin() + static_cast<long>(i))) {
      std::copy(to.begin(), to.end(), renamed.begin() + static_cast<long>(i));
      ++replaced;
    }
  ASSERT_GT(replaced, 2u);
  const std::string odd = dir.file("odd.mcap");
  write_all(odd, renamed);
  EXPECT_THAT(input_error_of([&] { io::Bag b(odd); }), HasSubstr("unknown compression 'br9'"));
  EXPECT_THAT(input_error_of([&] { io::Bag b(odd); }), HasSubstr(odd + ": record at byte"));
  io::McapWriterOptions bare = lz4;
  bare.summary = false;
  const std::string linear = dir.file("linear.mcap");
  write_sample(linear, bare);
  Bytes lb = read_all(linear);
  for (std::size_t i = 0; i + from.size() <= lb.size(); ++i)
    if (std::equal(from.begin(), from.end(), lb.begin() + static_cast<long>(i)))
      std::copy(to.begin(), to.end(), lb.begin() + static_cast<long>(i));
  write_all(linear, lb);
  EXPECT_THAT(input_error_of([&] { io::Bag b(linear); }), HasSubstr("unknown compression 'br9'"));

  // Cut in the middle: no footer, and the last record runs past the end.
  const std::string cut = dir.file("cut.mcap");
  write_all(cut, Bytes(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2)));
  EXPECT_THAT(input_error_of([&] { io::Bag b(cut); }), HasSubstr(cut + ": record at byte"));
  EXPECT_THAT(input_error_of([&] { io::Bag b(cut); }), HasSubstr("cut short"));

  // A damaged chunk (uncompressed, so a flipped byte decodes but fails its CRC).
  io::McapWriterOptions plain;
  plain.compression = "";
  const std::string crc = dir.file("crc.mcap");
  write_sample(crc, plain);
  Bytes cb = read_all(crc);
  cb[2000] ^= 0x40;
  write_all(crc, cb);
  EXPECT_THAT(input_error_of([&] {
                io::Bag b(crc);
                (void)b.read("/points", 0);
              }),
              HasSubstr("CRC mismatch"));

  // Not an MCAP file at all.
  const std::string text = dir.file("notes.mcap");
  write_text(text, "hello, this is text\n");
  EXPECT_THAT(input_error_of([&] { io::Bag b(text); }), HasSubstr(text + ": not an MCAP file"));
  // Garbage after a valid magic.
  Bytes junk(bytes.begin(), bytes.begin() + 8);
  junk.resize(200, 0xFF);
  const std::string j = dir.file("junk.mcap");
  write_all(j, junk);
  EXPECT_THAT(input_error_of([&] { io::Bag b(j); }), HasSubstr(j + ": record at byte 8"));
}

TEST(Rosbag2Writer, WritesABagTheReaderReadsBack) {
  TempDir dir;
  const std::string bag = dir.file("out_bag");
  {
    io::Rosbag2Writer w(bag);
    w.add_topic("/points", "sensor_msgs/msg/PointCloud2");
    for (int k = 4; k >= 0; --k) {
      const Bytes m = message(500 + static_cast<std::size_t>(k), static_cast<unsigned>(k));
      w.write("/points", 1000 + k, m.data(), m.size());
    }
    w.close();
  }
  EXPECT_FALSE(std::filesystem::exists(bag + ".part"));
  const io::Bag b(bag);
  ASSERT_EQ(b.message_count("/points"), 5u);
  EXPECT_EQ(b.topics()[0].type, "sensor_msgs/msg/PointCloud2");
  for (unsigned k = 0; k < 5; ++k) {
    EXPECT_EQ(b.message_time_ns("/points", k), 1000 + static_cast<std::int64_t>(k));
    EXPECT_EQ(b.read("/points", k), message(500 + k, k));
  }
  EXPECT_THAT(input_error_of([&] { io::Rosbag2Writer w(bag); }), HasSubstr("exists already"));
}

}  // namespace
}  // namespace dloam
