// Writes small seed inputs of the ROS 2 and packet harnesses from the shared data (scripts/fuzz.sh):
//   make_seeds clouds SCAN.bin OUT_DIR     PointCloud2 CDR messages, MCAP files (uncompressed, lz4,
//                                          zstd, unchunked), a rosbag2 .db3 and its metadata.yaml, of the
//                                          first points
//   make_seeds packets CAPTURE OUT N       the first N UDP payloads of a capture, each behind its
//                                          2-byte length (the fuzz_packets input)
//   make_seeds messages BAG OUT_DIR        the first message of each raw-packet topic of a ROS 2
//                                          bag, behind its type's index (the fuzz_packet_messages input),
//                                          and its first packets (a fuzz_packets input)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dloam/io/bag.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/pcap.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "dloam/io/rosbag2_writer.hpp"

namespace {
namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

void write(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void clouds(const std::string& scan_path, const std::string& out) {
  const dloam::PointCloud scan = dloam::io::read_kitti_bin(scan_path);
  std::vector<Bytes> messages;
  for (int k = 0; k < 3; ++k) {
    dloam::PointCloud cloud;
    for (std::size_t i = 0; i < 32 && 32 * k + i < scan.size(); ++i) {
      cloud.xyz.push_back(scan.xyz[32 * k + i]);
      cloud.intensity.push_back(scan.intensity[32 * k + i]);
      if (k != 1) cloud.time.push_back(static_cast<float>(i) / 32.0f);
    }
    messages.push_back(dloam::io::encode_pointcloud2(cloud, 100.0 + 0.1 * k, "velodyne"));
    write(out + "/cloud" + std::to_string(k) + ".cdr", messages.back());
  }
  struct Layout {
    const char* name;
    const char* compression;
    bool chunked;
  };
  for (const Layout l : {Layout{"plain", "", true}, Layout{"lz4", "lz4", true}, Layout{"zstd", "zstd", true},
                         Layout{"unchunked", "", false}}) {
    dloam::io::McapWriterOptions options;
    options.compression = l.compression;
    options.chunked = l.chunked;
    dloam::io::McapWriter w(out + "/" + l.name + ".mcap", options);
    const auto schema =
        w.add_schema(dloam::io::kPointCloud2Type, "ros2msg", dloam::io::pointcloud2_definition());
    const auto channel = w.add_channel("/points", "cdr", schema);
    for (std::size_t k = 0; k < messages.size(); ++k)
      w.write(channel, 100000000000ull + 100000000ull * k, messages[k].data(), messages[k].size());
    w.close();
  }
  const std::string bag = out + "/bag";
  fs::remove_all(bag);
  {
    dloam::io::Rosbag2Writer w(bag);
    w.add_topic("/points", dloam::io::kPointCloud2Type);
    for (std::size_t k = 0; k < messages.size(); ++k)
      w.write("/points", 100000000000ll + 100000000ll * static_cast<long long>(k), messages[k].data(),
              messages[k].size());
    w.close();
  }
  for (const auto& e : fs::directory_iterator(bag))
    if (e.path().extension() == ".db3")
      fs::copy_file(e.path(), out + "/cloud.db3", fs::copy_options::overwrite_existing);
  fs::copy_file(fs::path(bag) / "metadata.yaml", out + "/metadata.yaml",
                fs::copy_options::overwrite_existing);
  fs::remove_all(bag);
}

void packets(const std::string& capture, const std::string& out, std::size_t n) {
  dloam::io::PcapReader reader(capture);
  dloam::io::UdpDatagram d;
  Bytes bytes;
  for (std::size_t k = 0; k < n && reader.next(d); ++k) {
    const std::size_t size = std::min<std::size_t>(d.payload.size(), 0xffff);
    bytes.push_back(static_cast<std::uint8_t>(size & 0xff));
    bytes.push_back(static_cast<std::uint8_t>(size >> 8));
    bytes.insert(bytes.end(), d.payload.begin(), d.payload.begin() + static_cast<long>(size));
  }
  write(out, bytes);
}

void messages(const std::string& bag_path, const std::string& out) {
  const dloam::io::Bag bag(bag_path);
  const auto& types = dloam::io::packet_message_types();
  for (const auto& topic : bag.topics()) {
    const auto it = std::find(types.begin(), types.end(), topic.type);
    if (it == types.end() || bag.message_count(topic.name) == 0) continue;
    Bytes bytes{static_cast<std::uint8_t>(it - types.begin())};
    const Bytes message = bag.read(topic.name, 0);
    bytes.insert(bytes.end(), message.begin(), message.end());
    const std::string name =
        out + "/" + fs::path(bag_path).stem().string() + "-" + std::to_string(it - types.begin());
    write(name + ".msg", bytes);
    // Its first packets, as the fuzz_packets input.
    const auto decoded =
        dloam::io::decode_packet_message(topic.type, message.data(), message.size(), 0.0, name);
    Bytes framed;
    for (std::size_t k = 0; k < decoded.packets.size() && k < 8; ++k) {
      const auto& p = decoded.packets[k];
      const std::size_t size = std::min<std::size_t>(p.size, 0xffff);
      framed.push_back(static_cast<std::uint8_t>(size & 0xff));
      framed.push_back(static_cast<std::uint8_t>(size >> 8));
      framed.insert(framed.end(), message.begin() + static_cast<long>(p.offset),
                    message.begin() + static_cast<long>(p.offset + size));
    }
    write(name + ".packets", framed);
  }
}
}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> a(argv, argv + argc);
  try {
    if (a.size() == 4 && a[1] == "clouds") {
      clouds(a[2], a[3]);
    } else if (a.size() == 5 && a[1] == "packets") {
      packets(a[2], a[3], std::strtoul(a[4].c_str(), nullptr, 10));
    } else if (a.size() == 4 && a[1] == "messages") {
      messages(a[2], a[3]);
    } else {
      std::fprintf(
          stderr,
          "usage: make_seeds clouds SCAN.bin OUT_DIR | packets CAPTURE OUT N | messages BAG OUT_DIR\n");
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
