// Scan selection and writing a thinned copy of a sequence folder.
#include "dloam/io/thin.hpp"

#include <filesystem>
#include <random>
#include <stdexcept>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace fs = std::filesystem;
using detail::fail;

void ThinOptions::validate() const {
  if (keep_every < 1) throw std::invalid_argument("thin: keep-every must be at least 1");
  if (!(drop >= 0.0 && drop < 1.0)) throw std::invalid_argument("thin: drop probability must be in [0, 1)");
}

std::vector<std::size_t> select_scans(std::size_t n, const ThinOptions& o) {
  o.validate();
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = unit(rng);  // drawn for every scan: the choice of scan i does not depend on N
    if (i % static_cast<std::size_t>(o.keep_every) == 0 && !(u < o.drop)) kept.push_back(i);
  }
  if (kept.empty())
    throw std::invalid_argument("thin: no scan of " + std::to_string(n) + " is kept (drop " +
                                std::to_string(o.drop) + ", keep-every " + std::to_string(o.keep_every) +
                                ")");
  return kept;
}

namespace {
// The data lines of a text file (no blank or comment lines), as they are.
std::vector<std::string> data_lines(const std::string& path) {
  std::vector<std::string> out;
  for (auto& line : detail::split_lines(read_file(path, kMaxTableFileBytes)))
    if (!detail::is_blank_or_comment(line)) out.push_back(std::move(line));
  return out;
}

void write_lines(const std::string& path, const std::vector<std::string>& lines) {
  write_atomic(path, [&](std::ostream& out) {
    for (const auto& l : lines) out << l << '\n';
  });
}

// Hard link `from` as `to`, or copy it when linking is not possible; true when linked.
bool link_or_copy(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::remove(to, ec);
  fs::create_hard_link(from, to, ec);
  if (!ec) return true;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (ec) fail(to.string(), "cannot copy " + from.string() + " here (" + ec.message() + ")");
  return false;
}

bool inside(const fs::path& dir, const fs::path& root) {
  for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
    if (p == root) return true;
    if (p == p.parent_path()) break;
  }
  return false;
}

// Removes the scans and labels an earlier run left in `folder` (refusing without `overwrite`).
void clear_folder(const fs::path& folder, const std::vector<std::string>& extensions, bool overwrite) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> old;
  for (const auto& f : fs::directory_iterator(folder))
    for (const auto& e : extensions)
      if (f.is_regular_file() && f.path().extension() == e) old.push_back(f.path());
  if (!old.empty() && !overwrite)
    fail(folder.string(), "already holds " + std::to_string(old.size()) +
                              " scan or label files; use --overwrite or another --out");
  for (const auto& f : old) fs::remove(f);
}
}  // namespace

ThinResult thin_sequence(const std::string& in, const std::string& out, const ThinOptions& options,
                         double scan_rate_hz, bool overwrite) {
  std::error_code ec;
  if (fs::is_regular_file(in, ec))
    fail(in, "thin works on sequence folders (scans in files), not on one file");
  const Sequence seq = open_sequence(in);
  if (!(scan_rate_hz > 0.0)) fail(in, "scan rate must be positive to give nominal times");
  const fs::path in_abs = fs::weakly_canonical(fs::absolute(in)),
                 out_abs = fs::weakly_canonical(fs::absolute(out));
  if (inside(out_abs, in_abs))
    fail(out, "is the input folder or inside it; thin never writes into its input");

  ThinResult result;
  result.input_scans = seq.size();
  try {
    result.kept = select_scans(seq.size(), options);
  } catch (const std::invalid_argument& e) {
    fail(in, e.what());
  }
  // Same layout as the input: the scans' folder relative to the sequence folder.
  const fs::path scan_dir_rel = fs::relative(fs::path(seq.scan_files.front()).parent_path(), in_abs);
  const fs::path scan_dir = fs::path(out) / scan_dir_rel, label_dir = fs::path(out) / "labels";
  fs::create_directories(scan_dir, ec);
  if (ec) fail(scan_dir.string(), "cannot create folder (" + ec.message() + ")");
  clear_folder(scan_dir, {".bin", ".pcd"}, overwrite);
  if (seq.has_labels()) {
    fs::create_directories(label_dir, ec);
    if (ec) fail(label_dir.string(), "cannot create folder (" + ec.message() + ")");
    clear_folder(label_dir, {".label"}, overwrite);
  }

  std::vector<std::string> kept_lines;
  for (std::size_t k = 0; k < result.kept.size(); ++k) {
    const std::size_t i = result.kept[k];
    const fs::path src(seq.scan_files[i]);
    const std::string name = scan_name(k);
    result.hard_links &= link_or_copy(src, scan_dir / (name + src.extension().string()));
    if (seq.has_labels())
      result.hard_links &= link_or_copy(seq.label_files[i], label_dir / (name + ".label"));
    kept_lines.push_back(std::to_string(i));
  }

  const SequenceFiles files = list_sequence_files(in);
  if (seq.has_poses()) {
    const fs::path path = fs::path(out) / "poses.txt";
    if (result.kept.front() == 0) {
      const std::vector<std::string> lines = data_lines(files.poses_file);
      std::vector<std::string> kept;
      for (std::size_t i : result.kept) kept.push_back(lines[i]);
      write_lines(path.string(), kept);
    } else {  // KITTI convention: relative to the first scan of the sequence
      const Pose first_inv = seq.poses[result.kept.front()].inverse();
      std::vector<Pose> kept;
      for (std::size_t i : result.kept) kept.push_back(first_inv * seq.poses[i]);
      write_kitti_poses(path.string(), kept);
    }
  }
  if (!seq.times.empty()) {
    const std::vector<std::string> lines = data_lines(files.times_file);
    std::vector<std::string> kept;
    for (std::size_t i : result.kept) kept.push_back(lines[i]);
    write_lines((fs::path(out) / "times.txt").string(), kept);
  } else {
    std::vector<double> times;
    for (std::size_t i : result.kept) times.push_back(static_cast<double>(i) / scan_rate_hz);
    write_times((fs::path(out) / "times.txt").string(), times);
  }
  if (!files.calib_file.empty()) {
    fs::copy_file(files.calib_file, fs::path(out) / "calib.txt", fs::copy_options::overwrite_existing, ec);
    if (ec)
      fail((fs::path(out) / "calib.txt").string(),
           "cannot copy " + files.calib_file + " (" + ec.message() + ")");
  }
  write_lines((fs::path(out) / "kept_scans.txt").string(), kept_lines);
  return result;
}

}  // namespace dloam::io
