// `dloam run`'s output folder: an flock(2) on DIR/.dloam.lock, and the stale outputs of an earlier run.
#include "output_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::app {

namespace {
namespace fs = std::filesystem;

constexpr const char* kOutputs[] = {"poses.txt",    "poses_tum.txt", "poses_gt.txt", "calib.txt",
                                    "map.ply",      "moving.ply",    "timing.csv",   "config.yaml",
                                    "metrics.json", "report.html"};

/// The outputs of an earlier run in `dir`, and their temporary files.
std::vector<fs::path> earlier_outputs(const fs::path& dir) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const char* name : kOutputs)
    for (const std::string& file : {std::string(name), std::string(name) + ".tmp"})
      if (fs::symlink_status(dir / file, ec).type() != fs::file_type::not_found) found.push_back(dir / file);
  const fs::path labels = dir / "labels";
  if (fs::is_directory(labels, ec)) {
    fs::directory_iterator it(labels, ec);
    for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      const bool label = it->path().extension() == ".label" ||
                         (name.size() > 10 && name.compare(name.size() - 10, 10, ".label.tmp") == 0);
      if (label) found.push_back(it->path());
    }
    if (ec) throw InputError(labels.string() + ": cannot be listed (" + ec.message() + ")");
  }
  return found;
}

bool same_folder(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;
}
}  // namespace

OutputDir::OutputDir(const std::string& dir, const std::string& input_dir, bool overwrite) : dir_(dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw InputError(dir + ": cannot create the output folder" + (ec ? " (" + ec.message() + ")" : ""));
  if (same_folder(dir, input_dir))
    throw InputError(dir +
                     ": is the input sequence folder; choose another --out (its poses.txt and labels/ "
                     "are the input's)");
  if (fs::exists(fs::path(dir) / "velodyne", ec))
    throw InputError(dir + ": holds a velodyne/ folder (a sequence); choose another --out");

  const std::string lock = (fs::path(dir) / ".dloam.lock").string();
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw InputError(lock + ": cannot create the lock file (" + std::strerror(errno) + ")");
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err == EWOULDBLOCK)
      throw InputError(dir + ": another dloam run is writing into this folder (" + lock + " is locked)");
    throw InputError(lock + ": cannot lock (" + std::strerror(err) + ")");
  }

  const std::vector<fs::path> old = earlier_outputs(dir);
  if (old.empty()) return;
  if (!overwrite) {
    std::string list;
    std::size_t labels = 0;
    for (const auto& p : old) {
      if (p.parent_path().filename() == "labels") {
        ++labels;
      } else {
        list += (list.empty() ? "" : ", ") + p.filename().string();
      }
    }
    if (labels) list += (list.empty() ? "" : ", ") + ("labels/ (" + std::to_string(labels) + " files)");
    throw InputError(dir + ": holds the outputs of an earlier run (" + list +
                     "); pass --overwrite to replace them, or choose another --out");
  }
  for (const auto& p : old) {
    fs::remove(p, ec);
    if (ec) throw InputError(p.string() + ": cannot delete the earlier run's file (" + ec.message() + ")");
  }
}

OutputDir::~OutputDir() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock; the empty lock file stays
}

}  // namespace dloam::app
