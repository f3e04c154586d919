// Sequence folders (KITTI odometry / SemanticKITTI layout, or a folder of PCD scans): lists the
// files, checks that labels / poses / times agree with the scans, reads scans lazily.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/recording_sequence.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace fs = std::filesystem;
using detail::fail;

namespace {
std::vector<std::string> files_with_extension(const fs::path& folder, const std::string& ext) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && entry.path().extension() == ext) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string optional_file(const fs::path& dir, const char* name) {
  std::error_code ec;
  const fs::path p = dir / name;
  return fs::exists(p, ec) ? p.string() : std::string();
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

std::map<std::string, FileSequenceOpener>& file_formats() {
  static std::map<std::string, FileSequenceOpener> formats;
  return formats;
}

/// What a file holds, from its first bytes.
enum class Magic { kPcap, kSqlite, kMcap, kOther };
Magic sniff(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char h[16] = {0};
  in.read(reinterpret_cast<char*>(h), sizeof(h));
  const auto got = static_cast<std::size_t>(in.gcount());
  auto is = [&](std::initializer_list<unsigned char> m) {
    return got >= m.size() && std::equal(m.begin(), m.end(), h);
  };
  if (is({0xD4, 0xC3, 0xB2, 0xA1}) || is({0xA1, 0xB2, 0xC3, 0xD4}) || is({0x4D, 0x3C, 0xB2, 0xA1}) ||
      is({0xA1, 0xB2, 0x3C, 0x4D}) || is({0x0A, 0x0D, 0x0D, 0x0A}))
    return Magic::kPcap;
  if (got >= 16 && std::string(reinterpret_cast<char*>(h), 16) == std::string("SQLite format 3\0", 16))
    return Magic::kSqlite;
  if (is({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'})) return Magic::kMcap;
  return Magic::kOther;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Sequence open_sequence_file(const std::string& path, const InputOptions& input) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".pcap" || ext == ".pcapng" || ext == ".cap") return open_pcap_sequence(path, input);
  if (ext == ".db3" || ext == ".mcap") return open_bag2_sequence(path, input);
  const auto it = file_formats().find(ext);
  if (it != file_formats().end()) return it->second(path, input.topic);
  if (ext == ".bag")
    fail(path,
         "rosbag input needs dloam built with ROS (cmake -DDLOAM_WITH_ROS=ON and the Debian packages "
         "librosbag-storage-dev libsensor-msgs-dev)");
  switch (sniff(path)) {
    case Magic::kPcap:
      return open_pcap_sequence(path, input);
    case Magic::kSqlite:
    case Magic::kMcap:
      return open_bag2_sequence(path, input);
    case Magic::kOther:
      break;
  }
  fail(path,
       "is a file; expected a sequence folder, a capture (.pcap, .pcapng), a ROS 2 bag (.db3, .mcap, or a "
       "folder with metadata.yaml) or a ROS 1 bag (.bag)");
}

bool is_rosbag2_folder(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::is_regular_file(fs::path(path) / "metadata.yaml", ec);
}
}  // namespace

void register_sequence_format(const std::string& extension, FileSequenceOpener opener) {
  file_formats()[extension] = std::move(opener);
}

SequenceFiles list_sequence_files(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) fail(dir, "sequence folder not found");
  if (!fs::is_directory(dir, ec)) fail(dir, "is not a folder");
  SequenceFiles files;
  files.dir = dir;
  const fs::path root(dir);
  files.scan_files = files_with_extension(root / "velodyne", ".bin");
  if (files.scan_files.empty()) files.scan_files = files_with_extension(root / "velodyne", ".pcd");
  if (files.scan_files.empty()) files.scan_files = files_with_extension(root, ".pcd");
  if (files.scan_files.empty())
    fail(dir, "no scans found (expected velodyne/*.bin, velodyne/*.pcd or *.pcd)");
  files.has_label_dir = fs::is_directory(root / "labels", ec);
  files.label_files = files_with_extension(root / "labels", ".label");
  files.calib_file = optional_file(root, "calib.txt");
  files.poses_file = optional_file(root, "poses.txt");
  files.times_file = optional_file(root, "times.txt");
  return files;
}

PointCloud read_scan_file(const std::string& path) {
  if (fs::path(path).extension() == ".pcd") return read_pcd(path);
  return read_kitti_bin(path);
}

bool is_recording(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) || is_rosbag2_folder(path);
}

Sequence open_sequence(const std::string& dir, const std::string& topic) {
  InputOptions input;
  input.topic = topic;
  return open_sequence(dir, input);
}

Sequence open_sequence(const std::string& dir, const InputOptions& input) {
  std::error_code ec;
  if (fs::is_regular_file(dir, ec)) return open_sequence_file(dir, input);
  if (is_rosbag2_folder(dir)) return open_bag2_sequence(dir, input);
  if (!input.topic.empty()) fail(dir, "a topic applies to bags only");
  const SequenceFiles files = list_sequence_files(dir);
  Sequence seq;
  seq.dir = dir;
  seq.scan_files = files.scan_files;
  const std::size_t n = seq.scan_files.size();
  if (files.has_label_dir) {
    if (files.label_files.size() != n)
      fail(dir + "/labels", "has " + std::to_string(files.label_files.size()) +
                                " .label files but there are " + std::to_string(n) + " scans");
    for (std::size_t i = 0; i < n; ++i)
      if (stem(files.label_files[i]) != stem(seq.scan_files[i]))
        fail(files.label_files[i], "does not match scan " + seq.scan_files[i] + " (names must pair up)");
    seq.label_files = files.label_files;
  }
  if (!files.poses_file.empty()) {
    seq.poses = read_kitti_poses(files.poses_file);
    if (seq.poses.size() != n)
      fail(files.poses_file, "has " + std::to_string(seq.poses.size()) + " poses but there are " +
                                 std::to_string(n) + " scans");
  }
  if (!files.times_file.empty()) {
    seq.times = read_times(files.times_file);
    if (seq.times.size() != n)
      fail(files.times_file, "has " + std::to_string(seq.times.size()) + " times but there are " +
                                 std::to_string(n) + " scans");
  }
  if (!files.calib_file.empty()) seq.calib = read_calib(files.calib_file);
  return seq;
}

std::vector<Pose> Sequence::lidar_poses() const {
  if (calib && calib->has_Tr) return camera_to_lidar(poses, calib->Tr);
  return poses;
}

PointCloud Sequence::read_scan(std::size_t i) const {
  if (i >= scan_files.size())
    fail(dir, "scan index " + std::to_string(i) + " out of range (" + std::to_string(size()) + " scans)");
  PointCloud cloud = source ? source->read(i) : read_scan_file(scan_files[i]);
  if (i < times.size()) cloud.stamp = times[i];
  return cloud;
}

std::vector<Label> Sequence::read_scan_labels(std::size_t i, std::size_t n_points) const {
  if (!has_labels()) fail(dir, "has no labels/ folder");
  if (i >= label_files.size())
    fail(dir, "label index " + std::to_string(i) + " out of range (" + std::to_string(size()) + " scans)");
  return read_labels(label_files[i], n_points);
}

}  // namespace dloam::io
