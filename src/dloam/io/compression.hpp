// zstd and LZ4 (frame format) compression of byte buffers, for MCAP chunks and compressed
// rosbag2 messages. Internal to dloam_io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dloam::io::detail {

/// Decompresses a zstd frame of `expected` bytes (0: unknown, then up to `limit`). Throws
/// InputError "<where>: ..." for damaged data or a size other than `expected`.
std::vector<std::uint8_t> zstd_decompress(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                          const std::string& where, std::size_t limit = std::size_t{1} << 32);
std::vector<std::uint8_t> zstd_compress(const std::uint8_t* data, std::size_t size, int level = 3);
/// Streams a zstd-compressed file into `to` (a rosbag2 bag compressed per file).
void zstd_decompress_file(const std::string& from, const std::string& to);

/// LZ4 frame format (what MCAP's "lz4" means), same contract as zstd_decompress().
std::vector<std::uint8_t> lz4_decompress(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                         const std::string& where, std::size_t limit = std::size_t{1} << 32);
std::vector<std::uint8_t> lz4_compress(const std::uint8_t* data, std::size_t size);

}  // namespace dloam::io::detail
