// Atomic file writing (temp file + std::filesystem::rename) and bounded whole-file reading.
#include "dloam/io/atomic_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "dloam/core/types.hpp"

namespace dloam::io {

namespace fs = std::filesystem;

namespace {
std::string mebibytes(std::uintmax_t bytes) {
  const std::uintmax_t mib = bytes >> 20;
  return mib > 0 ? std::to_string(mib) + " MiB" : std::to_string(bytes) + " bytes";
}

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "is a folder, expected a file";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), expected a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "is a device, expected a regular file";
  if (S_ISSOCK(mode)) return "is a socket, expected a regular file";
  return "is not a regular file";
}
}  // namespace

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

std::string read_file(const std::string& path, std::uintmax_t max_bytes) {
  // stat() before open(): opening a FIFO for reading blocks until a writer appears.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT) throw InputError(path + ": file not found");
    throw InputError(path + ": cannot be read (" + std::strerror(err) + ")");
  }
  if (!S_ISREG(st.st_mode)) throw InputError(path + ": " + kind_of(st.st_mode));
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes)
    throw InputError(path + ": is " + mebibytes(size) + ", larger than any sane file of its kind (limit " +
                     mebibytes(max_bytes) + ")");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw InputError(path + ": read " + std::to_string(in.gcount()) + " of " + std::to_string(size) +
                     " bytes (the file shrank while it was read, or an I/O error)");
  if (in.peek() != std::char_traits<char>::eof())
    throw InputError(path + ": the file grew while it was read");
  return bytes;
}

}  // namespace dloam::io
