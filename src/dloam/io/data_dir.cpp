#include "dloam/io/data_dir.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "dloam/core/types.hpp"

#ifndef DLOAM_INSTALL_DATA_DIR
#define DLOAM_INSTALL_DATA_DIR ""
#endif

namespace dloam::io {

namespace {
namespace fs = std::filesystem;

constexpr const char* kMarker = "config/default.yaml";
constexpr int kParentLevels = 6;  // <prefix>/lib/python3.11/dist-packages/dloam/_dloam.so -> <prefix>

bool holds_data(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / kMarker, ec);
}

/// The file of the executable or shared object that holds this function.
std::optional<fs::path> this_binary() {
  Dl_info info{};
  std::error_code ec;
  if (dladdr(reinterpret_cast<void*>(&this_binary), &info) != 0 && info.dli_fname && *info.dli_fname) {
    const fs::path p(info.dli_fname);
    // The main program may be named as it was started (argv[0]); /proc/self/exe is exact.
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!p.is_absolute() && !ec && exe.filename() == p.filename()) return exe;
    const fs::path canonical = fs::weakly_canonical(p, ec);
    if (!ec && fs::is_regular_file(canonical, ec)) return canonical;
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) return exe;
  return std::nullopt;
}
}  // namespace

std::vector<std::string> data_dir_candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("DLOAM_DATA_DIR"); env && *env) out.emplace_back(env);
  if (const auto binary = this_binary()) {
    fs::path dir = binary->parent_path();
    for (int level = 0; level < kParentLevels && !dir.empty(); ++level) {
      out.push_back((dir / "share" / "dloam").string());
      if (dir == dir.parent_path()) break;
      dir = dir.parent_path();
    }
  }
  if (*DLOAM_INSTALL_DATA_DIR) out.emplace_back(DLOAM_INSTALL_DATA_DIR);
  return out;
}

std::optional<std::string> find_data_dir() {
  if (const char* env = std::getenv("DLOAM_DATA_DIR"); env && *env) {
    if (!holds_data(env))
      throw InputError(std::string("DLOAM_DATA_DIR=") + env + ": not a dloam data folder (no " + kMarker +
                       ")");
    return fs::path(env).lexically_normal().string();
  }
  for (const std::string& dir : data_dir_candidates())
    if (holds_data(dir)) return fs::path(dir).lexically_normal().string();
  return std::nullopt;
}

std::string data_dir() {
  if (auto dir = find_data_dir()) return *dir;
  std::string looked;
  for (const std::string& dir : data_dir_candidates()) looked += (looked.empty() ? "" : ", ") + dir;
  throw InputError("dloam's data folder (config/, models/) was not found (looked in " + looked +
                   "): set DLOAM_DATA_DIR to <install prefix>/share/dloam");
}

std::string model_dir() {
  const auto dir = find_data_dir();
  return dir ? (fs::path(*dir) / "models").string() : std::string();
}

std::vector<std::string> shipped_configs() {
  std::vector<std::string> names;
  std::optional<std::string> dir;
  try {
    dir = find_data_dir();
  } catch (const InputError&) {  // DLOAM_DATA_DIR names no data folder: data_dir() reports it
  }
  if (!dir) return names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(*dir) / "config", ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string resolve_config_file(const std::string& name_or_path) {
  std::error_code ec;
  // Anything at the path (a folder, a FIFO, a device) is the user's file: the reader refuses it by kind.
  if (fs::exists(fs::symlink_status(name_or_path, ec))) return name_or_path;
  const auto dir = find_data_dir();
  // A name, not a path: look for it among the shipped configurations.
  if (dir && fs::path(name_or_path).filename() == fs::path(name_or_path)) {
    fs::path file = fs::path(*dir) / "config" / name_or_path;
    if (file.extension() != ".yaml") file += ".yaml";
    if (fs::is_regular_file(file, ec)) return file.string();
  }
  std::string names;
  for (const std::string& n : shipped_configs()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(name_or_path + ": no such config file" +
                   (names.empty() ? std::string(" (and no data folder with shipped configurations was found)")
                                  : " or shipped configuration (" + names + ")"));
}

}  // namespace dloam::io
