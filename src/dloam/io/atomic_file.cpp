// Atomic file writing (temp file + std::filesystem::rename) and whole-file reading.
#include "dloam/io/atomic_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "dloam/core/types.hpp"

namespace dloam::io {

namespace fs = std::filesystem;

void write_atomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const fs::path target(path);
  const fs::path tmp(path + ".tmp");
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open '" + tmp.string() + "' for writing");
    write(out);
    out.flush();
    if (!out) throw InputError(path + ": write failed (disk full or I/O error)");
    out.close();
    fs::rename(tmp, target, ec);
    if (ec) throw InputError(path + ": cannot rename the temporary file into place: " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": file not found");
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a folder, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return std::move(buffer).str();
}

}  // namespace dloam::io
