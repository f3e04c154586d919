// Sequence folders (KITTI odometry / SemanticKITTI layout, or a folder of PCD scans): lists the
// files in natural order, checks that labels / poses / times agree with the scans, reads scans lazily.
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/recording_sequence.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace fs = std::filesystem;
using detail::fail;

namespace {
bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

/// The entries of `folder` whose extension is `ext` (any file type but folders), natural order.
std::vector<std::string> files_with_extension(const fs::path& folder, const std::string& ext) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  fs::directory_iterator it(folder, ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (it->path().extension() != ext) continue;
    std::error_code type_ec;
    if (it->is_directory(type_ec)) continue;
    files.push_back(it->path().string());
  }
  if (ec) fail(folder.string(), "cannot be listed (" + ec.message() + ")");
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return natural_less(fs::path(a).filename().string(), fs::path(b).filename().string());
  });
  return files;
}

std::string optional_file(const fs::path& dir, const char* name) {
  std::error_code ec;
  const fs::path p = dir / name;
  // A dangling link or a link loop is "there" too: reading it names the problem.
  return fs::symlink_status(p, ec).type() != fs::file_type::not_found && !ec ? p.string() : std::string();
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

/// One description per gap in the numbers of scans named by numbers only; throws when two scans
/// carry the same number ("5.bin" and "005.bin").
std::vector<std::string> find_numbering_gaps(const std::vector<std::string>& files) {
  std::vector<std::string> gaps;
  std::vector<unsigned long long> numbers;
  for (const auto& f : files) {
    const std::string s = stem(f);
    if (s.empty() || s.size() > 18 || !std::all_of(s.begin(), s.end(), is_digit)) return gaps;
    numbers.push_back(std::stoull(s));
  }
  for (std::size_t i = 1; i < numbers.size(); ++i) {
    if (numbers[i] == numbers[i - 1]) fail(files[i], "has the same scan number as " + files[i - 1]);
    if (numbers[i] != numbers[i - 1] + 1)
      gaps.push_back("scan numbers skip from " + stem(files[i - 1]) + " to " + stem(files[i]) + " (" +
                     std::to_string(numbers[i] - numbers[i - 1] - 1) + " missing)");
  }
  return gaps;
}

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

/// Throws naming the first scan that is not a regular file (read_file's message).
void check_regular_files(const std::vector<std::string>& files) {
  for (const auto& f : files) {
    struct stat st {};
    if (::stat(f.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
      (void)read_file(f, 0);  // throws the reason: not found / link loop / FIFO / device ...
  }
}
}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && is_digit(a[ie])) ++ie;
      while (je < b.size() && is_digit(b[je])) ++je;
      std::size_t is = i, js = j;  // skip leading zeros, then the longer number is larger
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      const int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      if (ie - i != je - j) return ie - i < je - j;  // same value: fewer leading zeros first
      i = ie;
      j = je;
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

void register_sequence_format(const std::string& extension, FileSequenceOpener opener) {
  file_formats()[extension] = std::move(opener);
}

SequenceFiles list_sequence_files(const std::string& dir) {
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (status.type() == fs::file_type::not_found) fail(dir, "sequence folder not found");
  if (ec) fail(dir, "cannot be opened (" + ec.message() + ")");
  if (status.type() != fs::file_type::directory) fail(dir, "is not a folder");
  SequenceFiles files;
  files.dir = dir;
  const fs::path root(dir);
  files.scan_files = files_with_extension(root / "velodyne", ".bin");
  if (files.scan_files.empty()) files.scan_files = files_with_extension(root / "velodyne", ".pcd");
  if (files.scan_files.empty()) files.scan_files = files_with_extension(root, ".pcd");
  if (files.scan_files.empty())
    fail(dir, "no scans found (expected velodyne/*.bin, velodyne/*.pcd or *.pcd)");
  files.numbering_gaps = find_numbering_gaps(files.scan_files);
  files.has_label_dir = fs::is_directory(root / "labels", ec);
  files.label_files = files_with_extension(root / "labels", ".label");
  files.calib_file = optional_file(root, "calib.txt");
  files.poses_file = optional_file(root, "poses.txt");
  files.times_file = optional_file(root, "times.txt");
  return files;
}

PointCloud read_scan_file(const std::string& path, ScanInfo* info) {
  if (fs::path(path).extension() == ".pcd") return read_pcd(path, info);
  PointCloud cloud = read_kitti_bin(path);
  if (info) *info = ScanInfo{cloud.size(), {}};
  return cloud;
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
  check_regular_files(files.scan_files);
  Sequence seq;
  seq.dir = dir;
  seq.scan_files = files.scan_files;
  const std::size_t n = seq.scan_files.size();
  if (!files.numbering_gaps.empty()) {
    const std::string gaps = files.numbering_gaps.front() +
                             (files.numbering_gaps.size() > 1
                                  ? " and " + std::to_string(files.numbering_gaps.size() - 1) + " more gaps"
                                  : "");
    const std::string paired = !files.poses_file.empty() ? files.poses_file : files.times_file;
    if (!paired.empty())
      fail(paired, "pairs with the scans by line, but the " + gaps +
                       ": its lines cannot be matched to the scans (fill the gap or renumber the scans)");
    seq.warnings.push_back(dir + ": " + gaps);
  }
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
  if (poses_frame_unknown())
    fail(dir + "/calib.txt",
         "has no Tr (velodyne -> camera 0), so the frame of poses.txt is unknown (KITTI poses are "
         "camera-frame poses); add Tr, or pass --gt-frame lidar when poses.txt is in the LiDAR frame");
  if (calib && calib->has_Tr) return camera_to_lidar(poses, calib->Tr);
  return poses;
}

PointCloud Sequence::read_scan(std::size_t i, ScanInfo* info) const {
  if (i >= scan_files.size())
    fail(dir, "scan index " + std::to_string(i) + " out of range (" + std::to_string(size()) + " scans)");
  PointCloud cloud;
  if (source) {
    cloud = source->read(i);
    if (info) *info = ScanInfo{cloud.size(), {}};
  } else {
    cloud = read_scan_file(scan_files[i], info);
  }
  if (i < times.size()) cloud.stamp = times[i];
  return cloud;
}

std::vector<Label> Sequence::read_scan_labels(std::size_t i, std::size_t n_points,
                                              const ScanInfo* info) const {
  if (!has_labels()) fail(dir, "has no labels/ folder");
  if (i >= label_files.size())
    fail(dir, "label index " + std::to_string(i) + " out of range (" + std::to_string(size()) + " scans)");
  if (!info || info->kept.empty()) return read_labels(label_files[i], n_points);
  const std::vector<Label> all = read_labels(label_files[i], info->file_points);
  std::vector<Label> kept;
  kept.reserve(info->kept.size());
  for (const std::size_t k : info->kept) kept.push_back(all[k]);
  if (kept.size() != n_points)
    fail(label_files[i], "the scan has " + std::to_string(n_points) + " points but " +
                             std::to_string(kept.size()) + " were read");
  return kept;
}

std::string Sequence::output_name(std::size_t i) const {
  if (source || i >= scan_files.size()) return scan_name(i);
  return stem(scan_files[i]);
}

}  // namespace dloam::io
