// Atomic file writing (temp file + rename) and whole-file reading for every dloam file format.
// An interrupted run never leaves a half-written file: readers see the old file or the new one.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace dloam::io {

/// Writes `path` atomically: `write` fills a binary stream on `path.tmp`, which is renamed over
/// `path` once it is complete. Missing parent folders are created. Throws dloam::InputError
/// naming the file when it cannot be written.
void write_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

/// The whole file as bytes; throws dloam::InputError when it is missing or unreadable.
std::string read_file(const std::string& path);

}  // namespace dloam::io
