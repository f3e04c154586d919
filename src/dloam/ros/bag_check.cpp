// ROS 1 bag format 2.0 (http://wiki.ros.org/Bags/Format/2.0), walked record by record, and the
// lengths of a serialised PointCloud2 (see bag_check.hpp).
#include "dloam/ros/bag_check.hpp"

#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <string_view>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::ros1 {

namespace {
constexpr std::uint8_t kMessageData = 0x02, kBagHeader = 0x03, kIndexData = 0x04, kChunk = 0x05,
                       kChunkInfo = 0x06, kConnection = 0x07;
constexpr std::uint32_t kMaxHeader = 1u << 20;               // bytes of one record header
constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 30;  // uncompressed bytes of one chunk
constexpr std::uint64_t kMaxRatio = 1000;                    // uncompressed / compressed

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

class Walker {
 public:
  Walker(const std::string& path, std::ifstream& in) : path_(path), in_(in) {}

  [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
    throw InputError(path_ + ": not a readable rosbag (byte " + std::to_string(at) + ": " + what + ")");
  }

  /// Reads `n` bytes at `at`, within [at, limit).
  std::string read(std::uint64_t at, std::uint64_t n, std::uint64_t limit) {
    if (n > limit - at || at > limit)
      fail(at, "a length of " + std::to_string(n) + " bytes runs past its end");
    std::string bytes(static_cast<std::size_t>(n), '\0');
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(bytes.data(), static_cast<std::streamsize>(n));
    if (static_cast<std::uint64_t>(in_.gcount()) != n) fail(at, "the file ends inside a record");
    return bytes;
  }

  /// The `name=value` fields of a header block.
  std::map<std::string, std::string> fields(const std::string& block, std::uint64_t at) const {
    std::map<std::string, std::string> out;
    std::size_t i = 0;
    while (i < block.size()) {
      if (block.size() - i < 4) fail(at + i, "a header field is cut off");
      const std::uint32_t len = load<std::uint32_t>(block.data() + i);
      i += 4;
      if (len > block.size() - i)
        fail(at + i, "a header field of " + std::to_string(len) + " bytes runs past its header");
      const std::string_view field(block.data() + i, len);
      const std::size_t eq = field.find('=');
      if (eq == std::string_view::npos) fail(at + i, "a header field without '='");
      if (!out.emplace(std::string(field.substr(0, eq)), std::string(field.substr(eq + 1))).second)
        fail(at + i, "a header field given twice");
      i += len;
    }
    return out;
  }

  struct Record {
    std::uint64_t at = 0, data_at = 0, data_len = 0;
    std::uint8_t op = 0;
    std::map<std::string, std::string> fields;
  };

  /// The record at `at`, within [at, limit).
  Record record(std::uint64_t at, std::uint64_t limit) {
    Record r;
    r.at = at;
    const std::uint32_t header_len = load<std::uint32_t>(read(at, 4, limit).data());
    if (header_len > kMaxHeader) fail(at, "a record header of " + std::to_string(header_len) + " bytes");
    r.fields = fields(read(at + 4, header_len, limit), at + 4);
    const std::uint64_t len_at = at + 4 + header_len;
    r.data_len = load<std::uint32_t>(read(len_at, 4, limit).data());
    r.data_at = len_at + 4;
    if (r.data_len > limit - r.data_at)
      fail(len_at, "record data of " + std::to_string(r.data_len) + " bytes runs past its end");
    const auto op = r.fields.find("op");
    if (op == r.fields.end() || op->second.size() != 1) fail(at, "a record without a 1-byte op field");
    r.op = static_cast<std::uint8_t>(op->second[0]);
    return r;
  }

  /// A numeric field of exactly sizeof(T) bytes.
  template <class T>
  T number(const Record& r, const char* name) const {
    const auto it = r.fields.find(name);
    if (it == r.fields.end()) fail(r.at, std::string("a record without its '") + name + "' field");
    if (it->second.size() != sizeof(T))
      fail(r.at, std::string("field '") + name + "' has " + std::to_string(it->second.size()) +
                     " bytes, expected " + std::to_string(sizeof(T)));
    return load<T>(it->second.data());
  }

 private:
  std::string path_;
  std::ifstream& in_;
};

std::uint32_t u32(std::string_view data, std::size_t& i, std::size_t at, const std::string& where) {
  if (data.size() - i < 4)
    throw InputError(where + ": cannot be read (message cut off at byte " + std::to_string(at + i) + ")");
  const std::uint32_t v = load<std::uint32_t>(data.data() + i);
  i += 4;
  return v;
}
}  // namespace

void check_bag_structure(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path + ": cannot open for reading");
  const auto file_size = static_cast<std::uint64_t>(in.tellg());
  Walker w(path, in);
  static const std::string kMagic = "#ROSBAG V2.0\n";
  if (file_size < kMagic.size() || w.read(0, kMagic.size(), file_size) != kMagic)
    w.fail(0, "no '#ROSBAG V2.0' line (only format 2.0 bags are read)");

  std::set<std::uint64_t> boundaries, chunks;
  std::vector<Walker::Record> chunk_infos;
  std::uint64_t index_pos = 0, connections = 0;
  std::uint32_t conn_count = 0, chunk_count = 0;
  bool have_header = false;
  for (std::uint64_t at = kMagic.size(); at < file_size;) {
    const Walker::Record r = w.record(at, file_size);
    boundaries.insert(at);
    switch (r.op) {
      case kBagHeader:
        if (have_header) w.fail(at, "a second bag header");
        have_header = true;
        index_pos = w.number<std::uint64_t>(r, "index_pos");
        conn_count = w.number<std::uint32_t>(r, "conn_count");
        chunk_count = w.number<std::uint32_t>(r, "chunk_count");
        break;
      case kChunk: {
        chunks.insert(at);
        const auto compression = r.fields.find("compression");
        const std::uint32_t size = w.number<std::uint32_t>(r, "size");
        if (compression == r.fields.end()) w.fail(at, "a chunk without compression field");
        if (compression->second == "none") {
          if (size != r.data_len) w.fail(at, "an uncompressed chunk whose size differs from its data");
          std::set<std::uint64_t> inner;  // offsets of the records inside, from the chunk's data start
          for (std::uint64_t c = r.data_at; c < r.data_at + r.data_len;) {
            const Walker::Record m = w.record(c, r.data_at + r.data_len);
            if (m.op != kMessageData && m.op != kConnection)
              w.fail(c, "a record of op " + std::to_string(m.op) + " inside a chunk");
            (void)w.number<std::uint32_t>(m, "conn");
            if (m.op == kMessageData) (void)w.number<std::uint64_t>(m, "time");
            if (m.op == kConnection) (void)w.fields(w.read(m.data_at, m.data_len, file_size), m.data_at);
            inner.insert(c - r.data_at);
            c = m.data_at + m.data_len;
          }
          // The index records after the chunk point into it.
          std::uint64_t next = r.data_at + r.data_len;
          while (next < file_size) {
            const Walker::Record ix = w.record(next, file_size);
            if (ix.op != kIndexData) break;
            const std::uint32_t count = w.number<std::uint32_t>(ix, "count");
            if (w.number<std::uint32_t>(ix, "ver") != 1) w.fail(next, "an index record of another version");
            (void)w.number<std::uint32_t>(ix, "conn");
            if (std::uint64_t{count} * 12 != ix.data_len)
              w.fail(next, "an index record whose count does not fit its data");
            const std::string entries = w.read(ix.data_at, ix.data_len, file_size);
            for (std::uint32_t k = 0; k < count; ++k)
              if (!inner.count(load<std::uint32_t>(entries.data() + 12 * k + 8)))
                w.fail(ix.data_at + 12 * k, "an index entry that points between the chunk's records");
            boundaries.insert(next);
            next = ix.data_at + ix.data_len;
          }
          at = next;
          continue;
        }
        if (compression->second != "bz2" && compression->second != "lz4")
          w.fail(at, "unknown chunk compression '" + compression->second + "'");
        if (size > kMaxChunk || size > kMaxRatio * r.data_len + 4096)
          w.fail(at, "a compressed chunk of " + std::to_string(r.data_len) + " bytes claims " +
                         std::to_string(size) + " uncompressed");
        break;
      }
      case kIndexData: {
        const std::uint32_t count = w.number<std::uint32_t>(r, "count");
        if (w.number<std::uint32_t>(r, "ver") != 1) w.fail(at, "an index record of another version");
        (void)w.number<std::uint32_t>(r, "conn");
        if (std::uint64_t{count} * 12 != r.data_len)
          w.fail(at, "an index record whose count does not fit its data");
        break;
      }
      case kConnection:
        (void)w.number<std::uint32_t>(r, "conn");
        (void)w.fields(w.read(r.data_at, r.data_len, file_size), r.data_at);
        ++connections;
        break;
      case kChunkInfo:
        if (w.number<std::uint32_t>(r, "ver") != 1) w.fail(at, "a chunk-info record of another version");
        (void)w.number<std::uint64_t>(r, "start_time");
        (void)w.number<std::uint64_t>(r, "end_time");
        if (std::uint64_t{w.number<std::uint32_t>(r, "count")} * 8 != r.data_len)
          w.fail(at, "a chunk-info record whose count does not fit its data");
        chunk_infos.push_back(r);
        break;
      case kMessageData:
        (void)w.number<std::uint32_t>(r, "conn");
        (void)w.number<std::uint64_t>(r, "time");
        break;
      default:
        w.fail(at, "a record of unknown op " + std::to_string(r.op));
    }
    at = r.data_at + r.data_len;
  }
  if (!have_header) w.fail(kMagic.size(), "no bag header record");
  if (index_pos == 0)
    w.fail(kMagic.size(), "the bag was not closed (index position 0): reindex it with `rosbag reindex`");
  if (!boundaries.count(index_pos))
    w.fail(kMagic.size(), "the index position " + std::to_string(index_pos) + " is not a record");
  if (conn_count > connections || chunk_count > chunk_infos.size())
    w.fail(kMagic.size(), "the bag header counts more connections or chunks than the file holds");
  for (const auto& info : chunk_infos)
    if (!chunks.count(w.number<std::uint64_t>(info, "chunk_pos")))
      w.fail(info.at, "a chunk-info record that points to no chunk");
}

void check_pointcloud2_lengths(const std::uint8_t* bytes, std::size_t size, const std::string& where) {
  const std::string_view data(reinterpret_cast<const char*>(bytes), size);
  std::size_t i = 0;
  auto skip = [&](std::uint64_t n) {
    if (n > data.size() - i)
      throw InputError(where + ": cannot be read (a length of " + std::to_string(n) + " bytes at byte " +
                       std::to_string(i) + " runs past the " + std::to_string(size) + "-byte message)");
    i += static_cast<std::size_t>(n);
  };
  skip(12);                      // header: seq, stamp
  skip(u32(data, i, 0, where));  // frame_id
  skip(8);                       // height, width
  const std::uint32_t fields = u32(data, i, 0, where);
  if (fields > (data.size() - i) / 13) skip(std::uint64_t{fields} * 13);  // each at least 13 bytes: fails
  for (std::uint32_t f = 0; f < fields; ++f) {
    skip(u32(data, i, 0, where));  // name
    skip(9);                       // offset, datatype, count
  }
  skip(9);                       // is_bigendian, point_step, row_step
  skip(u32(data, i, 0, where));  // data
  skip(1);                       // is_dense
}

}  // namespace dloam::ros1
