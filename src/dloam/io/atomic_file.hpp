// Atomic file writing (temp file + rename) and bounded whole-file reading for every dloam file
// format. An interrupted run never leaves a half-written file: readers see the old file or the new
// one. Reading refuses what is not a regular file (a FIFO would block, a device never ends) and
// files larger than any sane instance of their format, before anything is allocated.
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace dloam::io {

/// Writes `path` atomically: `write` fills a binary stream on `path.tmp`, which is renamed over
/// `path` once it is complete. Missing parent folders are created. Throws dloam::InputError
/// naming the file when it cannot be written.
void write_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Size limits of read_file(), per kind of file.
inline constexpr std::uintmax_t kMaxConfigFileBytes = std::uintmax_t{1} << 20;   ///< YAML config, calib.txt
inline constexpr std::uintmax_t kMaxTableFileBytes = std::uintmax_t{256} << 20;  ///< poses, times
inline constexpr std::uintmax_t kMaxDataFileBytes = std::uintmax_t{2} << 30;     ///< one scan, labels, map

/// The whole file as bytes. Throws dloam::InputError naming the file when it is missing, not a
/// regular file (folder, FIFO, device, socket; symlinks are followed), larger than `max_bytes`,
/// or unreadable.
std::string read_file(const std::string& path, std::uintmax_t max_bytes = kMaxDataFileBytes);

}  // namespace dloam::io
