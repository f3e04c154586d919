// MCAP (https://mcap.dev/spec), the default storage of ROS 2 bags since Iron. Reading goes through
// io::Bag (bag.hpp): chunked or not; chunks uncompressed, lz4 or zstd; the summary section's
// chunk and message indexes when the file has them, a linear scan of the data section when not.
// This header adds the writer (chunked, optional lz4 / zstd, message indexes and a summary, as
// the ros2 profile writes them) and an in-memory reader entry point for fuzzing.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dloam/io/bag.hpp"

namespace dloam::io {

struct McapWriterOptions {
  std::string compression = "zstd";               ///< chunk compression: "", "lz4" or "zstd"
  bool chunked = true;                            ///< false: messages written directly into the data section
  std::size_t chunk_size = std::size_t{4} << 20;  ///< uncompressed bytes per chunk before it is closed
  bool message_indexes = true;                    ///< Message Index records after each chunk
  bool summary = true;  ///< schemas, channels, chunk indexes, statistics and summary offsets
  std::string profile = "ros2";
};

/// Writes an MCAP file: `<path>.part`, renamed to `path` by close(), so an interrupted writer
/// leaves no half-written file under the final name.
class McapWriter {
 public:
  McapWriter(const std::string& path, McapWriterOptions options = {});
  ~McapWriter();  ///< without close(): the unfinished `.part` file is deleted
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema (ros2msg: the .msg definition text); returns its id.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  /// A channel (ros2: message encoding "cdr", metadata offered_qos_profiles); returns its id.
  std::uint16_t add_channel(const std::string& topic, const std::string& message_encoding,
                            std::uint16_t schema_id, const std::map<std::string, std::string>& metadata = {});
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, const std::uint8_t* data, std::size_t size,
             std::uint64_t publish_time_ns = 0, std::uint32_t sequence = 0);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

namespace bag_detail {
/// An MCAP file held in memory (fuzzing, tests); `name` is used in errors.
std::unique_ptr<BagFile> open_mcap_memory(std::vector<std::uint8_t> bytes, const std::string& name);
}  // namespace bag_detail

}  // namespace dloam::io
