// MCAP reading (see mcap.hpp, bag.hpp): the index of every message is built when the file is
// opened, from the summary's chunk indexes and the message indexes when the file has them, else
// by one linear scan of the data section; messages are read (their chunk decompressed, the last
// few kept) when asked for.
#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <list>
#include <map>
#include <set>

#include "dloam/core/types.hpp"
#include "dloam/io/bag.hpp"
#include "dloam/io/bytes.hpp"
#include "dloam/io/compression.hpp"
#include "dloam/io/mcap.hpp"

namespace dloam::io::bag_detail {

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 30;  ///< uncompressed bytes of one chunk
constexpr int kChunkShift = 40;                              ///< locator = (chunk + 1) << 40 | offset

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kDataEnd = 0x0F,
};

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

/// Where the bytes come from: a file (read with pread) or memory.
class Source {
 public:
  Source(std::string name, std::vector<std::uint8_t> memory)
      : name_(std::move(name)), memory_(std::move(memory)) {
    size_ = memory_.size();
  }
  explicit Source(std::string path) : name_(std::move(path)) {
    fd_ = ::open(name_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) fail(name_, "cannot be opened");
    const off_t end = ::lseek(fd_, 0, SEEK_END);
    if (end < 0) {
      ::close(fd_);
      fd_ = -1;
      fail(name_, "cannot be read (not a regular file?)");
    }
    size_ = static_cast<std::uint64_t>(end);
  }
  ~Source() {
    if (fd_ >= 0) ::close(fd_);
  }
  Source(const Source&) = delete;
  Source& operator=(const Source&) = delete;

  [[nodiscard]] std::uint64_t size() const { return size_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  /// Bytes [offset, offset + n); throws when they are not all in the file.
  void read(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>& out, const char* what) const {
    if (offset > size_ || n > size_ - offset)
      fail(name_, std::string(what) + " at byte " + std::to_string(offset) + " (" + std::to_string(n) +
                      " bytes) runs past the end of the " + std::to_string(size_) +
                      "-byte file: the file is cut short or damaged");
    out.resize(n);
    if (!memory_.empty() || fd_ < 0) {
      std::copy(memory_.begin() + static_cast<long>(offset), memory_.begin() + static_cast<long>(offset + n),
                out.begin());
      return;
    }
    std::size_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, out.data() + done, n - done, static_cast<off_t>(offset + done));
      if (got <= 0) fail(name_, "read error at byte " + std::to_string(offset + done));
      done += static_cast<std::size_t>(got);
    }
  }

 private:
  std::string name_;
  std::vector<std::uint8_t> memory_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Bounds-checked little-endian fields of one record's content.
class Fields {
 public:
  Fields(const std::uint8_t* data, std::size_t size, std::string where)
      : p_(data), n_(size), where_(std::move(where)) {}
  template <class T>
  T get(const char* field) {
    need(sizeof(T), field);
    const T v = detail::load_le<T>(p_ + pos_);
    pos_ += sizeof(T);
    return v;
  }
  std::string string(const char* field) {
    const auto len = get<std::uint32_t>(field);
    need(len, field);
    std::string s(reinterpret_cast<const char*>(p_ + pos_), len);
    pos_ += len;
    return s;
  }
  /// uint32 byte length, then that many bytes (Map / Array / schema data).
  std::pair<const std::uint8_t*, std::size_t> prefixed32(const char* field) {
    const auto len = get<std::uint32_t>(field);
    need(len, field);
    const std::uint8_t* at = p_ + pos_;
    pos_ += len;
    return {at, len};
  }
  std::pair<const std::uint8_t*, std::size_t> prefixed64(const char* field) {
    const auto len = get<std::uint64_t>(field);
    need(len, field);
    const std::uint8_t* at = p_ + pos_;
    pos_ += static_cast<std::size_t>(len);
    return {at, static_cast<std::size_t>(len)};
  }
  std::pair<const std::uint8_t*, std::size_t> rest() { return {p_ + pos_, n_ - pos_}; }
  void need(std::uint64_t k, const char* field) const {
    if (k > n_ - pos_)
      fail(where_, std::string("record shorter than its fields (") + field + ": needs " + std::to_string(k) +
                       " bytes, " + std::to_string(n_ - pos_) + " left)");
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_, pos_ = 0;
  std::string where_;
};

struct Channel {
  std::string topic, encoding;
  std::uint16_t schema = 0;
};
struct Schema {
  std::string name, encoding;
};
struct Chunk {
  std::uint64_t offset = 0;  ///< of the chunk record
  std::uint64_t length = 0;  ///< whole record
};
/// The records of a decompressed chunk.
struct ChunkData {
  std::vector<std::uint8_t> records;
};

class McapFile : public BagFile {
 public:
  explicit McapFile(std::unique_ptr<Source> source) : src_(std::move(source)) {
    std::vector<std::uint8_t> head;
    if (src_->size() < 8) fail(src_->name(), "not an MCAP file (" + std::to_string(src_->size()) + " bytes)");
    src_->read(0, 8, head, "magic");
    if (!std::equal(head.begin(), head.end(), kMagic))
      fail(src_->name(), "not an MCAP file (no MCAP magic at the start)");
    if (!read_summary()) linear_scan();
    for (auto& [topic, refs] : refs_)
      std::stable_sort(refs.begin(), refs.end(),
                       [](const MessageRef& a, const MessageRef& b) { return a.time_ns < b.time_ns; });
  }

  [[nodiscard]] const std::string& path() const override { return src_->name(); }
  [[nodiscard]] std::string format() const override {
    std::string s = "MCAP";
    std::string what = chunks_.empty() ? "unchunked" : "chunked";
    for (const auto& c : compressions_) what += ", " + (c.empty() ? std::string("uncompressed") : c);
    s += " (" + what + (indexed_ ? ", indexed" : ", linear scan") + ")";
    return s;
  }

  std::vector<BagTopic> topics() override {
    std::map<std::string, BagTopic> by_name;
    for (const auto& [id, ch] : channels_) {
      BagTopic& t = by_name[ch.topic];
      const auto s = schemas_.find(ch.schema);
      const std::string type = s == schemas_.end() ? std::string() : s->second.name;
      if (!t.name.empty() && t.type != type)
        fail(src_->name(), "topic " + ch.topic + " has channels of types " + t.type + " and " + type);
      t.name = ch.topic;
      t.type = type;
      t.encoding = ch.encoding;
    }
    for (auto& [name, t] : by_name) {
      const auto it = refs_.find(name);
      t.messages = it == refs_.end() ? 0 : it->second.size();
    }
    std::vector<BagTopic> out;
    for (auto& [name, t] : by_name) out.push_back(t);
    return out;
  }

  std::vector<MessageRef> index(const std::string& topic) override {
    const auto it = refs_.find(topic);
    return it == refs_.end() ? std::vector<MessageRef>{} : it->second;
  }

  std::vector<std::uint8_t> read(const MessageRef& ref, const std::string& where) override {
    const std::uint64_t chunk = ref.locator >> kChunkShift;
    const std::uint64_t offset = ref.locator & ((std::uint64_t{1} << kChunkShift) - 1);
    std::vector<std::uint8_t> record;
    const std::uint8_t* rec = nullptr;
    std::size_t avail = 0;
    std::shared_ptr<const ChunkData> data;
    if (chunk == 0) {
      std::vector<std::uint8_t> head;
      src_->read(offset, 9, head, "message record");
      const std::uint64_t len = detail::load_le<std::uint64_t>(head.data() + 1);
      if (len > src_->size())
        fail(where, "message record length " + std::to_string(len) + " beyond the file");
      src_->read(offset, static_cast<std::size_t>(9 + len), record, "message record");
      rec = record.data();
      avail = record.size();
    } else {
      data = chunk_data(static_cast<std::size_t>(chunk - 1));
      if (offset > data->records.size()) fail(where, "message index points outside its chunk");
      rec = data->records.data() + offset;
      avail = data->records.size() - static_cast<std::size_t>(offset);
    }
    if (avail < 9 || rec[0] != kMessage) fail(where, "message index does not point at a message record");
    const std::uint64_t len = detail::load_le<std::uint64_t>(rec + 1);
    if (len > avail - 9) fail(where, "message record cut short");
    Fields f(rec + 9, static_cast<std::size_t>(len), where);
    (void)f.get<std::uint16_t>("channel_id");
    (void)f.get<std::uint32_t>("sequence");
    (void)f.get<std::uint64_t>("log_time");
    (void)f.get<std::uint64_t>("publish_time");
    const auto [p, n] = f.rest();
    return std::vector<std::uint8_t>(p, p + n);
  }

 private:
  [[nodiscard]] std::string at(std::uint64_t offset) const {
    return src_->name() + ": record at byte " + std::to_string(offset);
  }

  /// One record's opcode, content offset and length at `offset` of the file.
  struct RecordHead {
    std::uint8_t op = 0;
    std::uint64_t content = 0, length = 0;
  };
  RecordHead head_at(std::uint64_t offset) const {
    std::vector<std::uint8_t> h;
    src_->read(offset, 9, h, "record header");
    RecordHead r{h[0], offset + 9, detail::load_le<std::uint64_t>(h.data() + 1)};
    if (r.length > src_->size() - r.content)
      fail(at(offset), "(opcode " + std::to_string(r.op) + ", " + std::to_string(r.length) +
                           " bytes) runs past the end of the file: the file is cut short or damaged");
    return r;
  }

  void add_schema(Fields& f) {
    const auto id = f.get<std::uint16_t>("schema id");
    Schema s;
    s.name = f.string("schema name");
    s.encoding = f.string("schema encoding");
    (void)f.prefixed32("schema data");
    if (id != 0) schemas_[id] = s;
  }
  void add_channel(Fields& f) {
    const auto id = f.get<std::uint16_t>("channel id");
    Channel c;
    c.schema = f.get<std::uint16_t>("channel schema_id");
    c.topic = f.string("channel topic");
    c.encoding = f.string("channel message_encoding");
    (void)f.prefixed32("channel metadata");
    channels_[id] = c;
  }
  void add_message(std::uint16_t channel, std::uint64_t log_time, std::uint64_t locator,
                   const std::string& where) {
    const auto it = channels_.find(channel);
    if (it == channels_.end())
      fail(where, "message on channel " + std::to_string(channel) + ", which no Channel record defines");
    refs_[it->second.topic].push_back({static_cast<std::int64_t>(log_time), locator});
  }

  /// Chunk `c`'s records, decompressed and checked (CRC); the last few are cached.
  std::shared_ptr<const ChunkData> chunk_data(std::size_t c) {
    for (auto it = cache_.begin(); it != cache_.end(); ++it)
      if (it->first == c) {
        cache_.splice(cache_.begin(), cache_, it);
        return cache_.front().second;
      }
    const Chunk& chunk = chunks_.at(c);
    std::vector<std::uint8_t> rec;
    src_->read(chunk.offset, static_cast<std::size_t>(chunk.length), rec, "chunk record");
    const std::string where = at(chunk.offset) + " (chunk)";
    if (rec.size() < 9 || rec[0] != kChunk) fail(where, "is not a Chunk record");
    Fields f(rec.data() + 9, rec.size() - 9, where);
    (void)f.get<std::uint64_t>("message_start_time");
    (void)f.get<std::uint64_t>("message_end_time");
    const auto uncompressed = f.get<std::uint64_t>("uncompressed_size");
    const auto crc = f.get<std::uint32_t>("uncompressed_crc");
    const std::string compression = f.string("compression");
    const auto [p, n] = f.prefixed64("records");
    if (uncompressed > kMaxChunk)
      fail(where,
           "declares " + std::to_string(uncompressed) + " uncompressed bytes (more than 1 GiB is not read)");
    auto data = std::make_shared<ChunkData>();
    if (compression.empty()) {
      if (n != uncompressed)
        fail(where, "uncompressed chunk of " + std::to_string(n) + " bytes declares " +
                        std::to_string(uncompressed));
      data->records.assign(p, p + n);
    } else if (compression == "zstd") {
      data->records = detail::zstd_decompress(p, n, static_cast<std::size_t>(uncompressed), where);
    } else if (compression == "lz4") {
      data->records = detail::lz4_decompress(p, n, static_cast<std::size_t>(uncompressed), where);
    } else {
      fail(where, "unknown compression '" + compression + "' (none, lz4 and zstd are read)");
    }
    if (crc != 0) {
      const auto got = static_cast<std::uint32_t>(
          crc32(0L, data->records.data(), static_cast<uInt>(data->records.size())));
      if (got != crc) fail(where, "CRC mismatch: the chunk is damaged");
    }
    cache_.emplace_front(c, data);
    if (cache_.size() > 4) cache_.pop_back();
    return data;
  }

  /// Schemas, channels and messages of chunk `c` by walking its records.
  void scan_chunk(std::size_t c) {
    const auto data = chunk_data(c);
    const std::string where = at(chunks_[c].offset) + " (chunk)";
    const auto& r = data->records;
    std::size_t pos = 0;
    while (pos < r.size()) {
      if (r.size() - pos < 9) fail(where, "record inside the chunk cut short");
      const std::uint8_t op = r[pos];
      const std::uint64_t len = detail::load_le<std::uint64_t>(r.data() + pos + 1);
      if (len > r.size() - pos - 9) fail(where, "record inside the chunk cut short");
      Fields f(r.data() + pos + 9, static_cast<std::size_t>(len), where);
      if (op == kSchema) add_schema(f);
      if (op == kChannel) add_channel(f);
      if (op == kMessage) {
        const auto channel = f.get<std::uint16_t>("channel_id");
        (void)f.get<std::uint32_t>("sequence");
        const auto log_time = f.get<std::uint64_t>("log_time");
        add_message(channel, log_time, (static_cast<std::uint64_t>(c) + 1) << kChunkShift | pos, where);
      }
      pos += 9 + static_cast<std::size_t>(len);
    }
  }

  void add_chunk(std::uint64_t offset, std::uint64_t length) {
    if ((chunks_.size() + 1) >> (64 - kChunkShift) != 0) fail(src_->name(), "too many chunks");
    chunks_.push_back({offset, length});
  }

  /// Every record of the data section, in order: the index when the file has no usable summary.
  void linear_scan() {
    indexed_ = false;
    std::uint64_t pos = 8;
    const RecordHead h = head_at(pos);
    if (h.op != kHeader) fail(at(pos), "is not the Header record an MCAP file starts with");
    pos = h.content + h.length;
    std::vector<std::uint8_t> content;
    while (true) {
      if (pos == src_->size())
        fail(src_->name(), "ends at byte " + std::to_string(pos) +
                               " without a Data End or Footer record: the file is cut short");
      const RecordHead r = head_at(pos);
      if (r.op == kFooter || r.op == kDataEnd) break;
      if (r.op == kSchema || r.op == kChannel || r.op == kMessage) {
        src_->read(r.content, static_cast<std::size_t>(r.length), content, "record");
        Fields f(content.data(), content.size(), at(pos));
        if (r.op == kSchema) add_schema(f);
        if (r.op == kChannel) add_channel(f);
        if (r.op == kMessage) {
          const auto channel = f.get<std::uint16_t>("channel_id");
          (void)f.get<std::uint32_t>("sequence");
          add_message(channel, f.get<std::uint64_t>("log_time"), pos, at(pos));
        }
      } else if (r.op == kChunk) {
        add_chunk(pos, 9 + r.length);
        note_compression(pos);
        scan_chunk(chunks_.size() - 1);
      }
      pos = r.content + r.length;
    }
  }

  void note_compression(std::uint64_t chunk_offset) {
    std::vector<std::uint8_t> h;
    src_->read(chunk_offset + 9, 28 + 4, h, "chunk header");
    const auto len = detail::load_le<std::uint32_t>(h.data() + 28);
    if (len > 64) return;
    std::vector<std::uint8_t> name;
    src_->read(chunk_offset + 9 + 32, len, name, "chunk compression");
    compressions_.insert(std::string(name.begin(), name.end()));
  }

  /// Footer -> summary: schemas, channels, chunk indexes, then the message indexes of each
  /// chunk. False when the file has no summary with chunk indexes (or no footer).
  bool read_summary() {
    const std::uint64_t size = src_->size();
    if (size < 8 + 9 + 8 + 37) return false;
    std::vector<std::uint8_t> tail;
    src_->read(size - 37, 37, tail, "footer");
    if (!std::equal(tail.begin() + 29, tail.end(), kMagic) || tail[0] != kFooter ||
        detail::load_le<std::uint64_t>(tail.data() + 1) != 20)
      return false;  // cut short, or not finished: scan what is there
    const auto summary_start = detail::load_le<std::uint64_t>(tail.data() + 9);
    const auto summary_offset_start = detail::load_le<std::uint64_t>(tail.data() + 17);
    if (summary_start == 0) return false;
    const std::uint64_t end = summary_offset_start != 0 ? summary_offset_start : size - 37;
    if (summary_start > end || end > size - 37) fail(src_->name(), "footer points outside the file");
    struct Index {
      std::uint64_t offset, length;
      std::string compression;
      std::vector<std::pair<std::uint16_t, std::uint64_t>> message_indexes;
    };
    std::vector<Index> indexes;
    std::vector<std::uint8_t> content;
    for (std::uint64_t pos = summary_start; pos < end;) {
      const RecordHead r = head_at(pos);
      if (r.content + r.length > end) fail(at(pos), "runs past the summary section");
      if (r.op == kSchema || r.op == kChannel || r.op == kChunkIndex) {
        src_->read(r.content, static_cast<std::size_t>(r.length), content, "summary record");
        Fields f(content.data(), content.size(), at(pos));
        if (r.op == kSchema) add_schema(f);
        if (r.op == kChannel) add_channel(f);
        if (r.op == kChunkIndex) {
          Index idx;
          (void)f.get<std::uint64_t>("message_start_time");
          (void)f.get<std::uint64_t>("message_end_time");
          idx.offset = f.get<std::uint64_t>("chunk_start_offset");
          idx.length = f.get<std::uint64_t>("chunk_length");
          const auto [mp, mn] = f.prefixed32("message_index_offsets");
          if (mn % 10 != 0) fail(at(pos), "message_index_offsets map of " + std::to_string(mn) + " bytes");
          for (std::size_t k = 0; k < mn; k += 10)
            idx.message_indexes.emplace_back(detail::load_le<std::uint16_t>(mp + k),
                                             detail::load_le<std::uint64_t>(mp + k + 2));
          (void)f.get<std::uint64_t>("message_index_length");
          idx.compression = f.string("compression");
          indexes.push_back(std::move(idx));
        }
      }
      pos = r.content + r.length;
    }
    if (indexes.empty()) {
      schemas_.clear();
      channels_.clear();
      return false;  // unchunked: messages outside chunks are not indexed
    }
    for (const auto& idx : indexes) {
      if (idx.compression != "" && idx.compression != "lz4" && idx.compression != "zstd")
        fail(at(idx.offset) + " (chunk)",
             "unknown compression '" + idx.compression + "' (none, lz4 and zstd are read)");
      if (idx.offset >= size || idx.length > size - idx.offset)
        fail(src_->name(), "chunk index points outside the file");
      compressions_.insert(idx.compression);
      add_chunk(idx.offset, idx.length);
      const std::size_t c = chunks_.size() - 1;
      if (idx.message_indexes.empty()) {  // chunk without message indexes: walk it
        scan_chunk(c);
        continue;
      }
      for (const auto& [channel, offset] : idx.message_indexes) {
        const RecordHead r = head_at(offset);
        if (r.op != kMessageIndex)
          fail(at(offset), "is not the Message Index record the chunk index points at");
        src_->read(r.content, static_cast<std::size_t>(r.length), content, "message index");
        Fields f(content.data(), content.size(), at(offset));
        const auto id = f.get<std::uint16_t>("channel_id");
        const auto [p, n] = f.prefixed32("records");
        if (n % 16 != 0) fail(at(offset), "message index array of " + std::to_string(n) + " bytes");
        for (std::size_t k = 0; k < n; k += 16) {
          const auto t = detail::load_le<std::uint64_t>(p + k);
          const auto o = detail::load_le<std::uint64_t>(p + k + 8);
          if (o >> kChunkShift) fail(at(offset), "message offset beyond 1 TiB");
          add_message(id, t, (static_cast<std::uint64_t>(c) + 1) << kChunkShift | o, at(offset));
        }
        (void)channel;
      }
    }
    return true;
  }

  std::unique_ptr<Source> src_;
  std::map<std::uint16_t, Schema> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  std::vector<Chunk> chunks_;
  std::set<std::string> compressions_;
  std::map<std::string, std::vector<MessageRef>> refs_;
  std::list<std::pair<std::size_t, std::shared_ptr<const ChunkData>>> cache_;
  bool indexed_ = true;
};

}  // namespace

std::unique_ptr<BagFile> open_mcap_file(const std::string& path) {
  return std::make_unique<McapFile>(std::make_unique<Source>(path));
}

std::unique_ptr<BagFile> open_mcap_memory(std::vector<std::uint8_t> bytes, const std::string& name) {
  return std::make_unique<McapFile>(std::make_unique<Source>(name, std::move(bytes)));
}

}  // namespace dloam::io::bag_detail
