// MCAP writing (see mcap.hpp): Header; chunks (schemas and channels inside the chunk that first
// needs them), each followed by its Message Index records; Data End; the summary (schemas,
// channels, chunk indexes, statistics) and its Summary Offset records; Footer.
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <tuple>

#include "dloam/core/types.hpp"
#include "dloam/io/bytes.hpp"
#include "dloam/io/compression.hpp"
#include "dloam/io/mcap.hpp"

namespace dloam::io {

namespace {
constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

/// Little-endian record content.
struct Buf {
  std::vector<std::uint8_t> b;
  template <class T>
  void put(T v) {
    const std::size_t at = b.size();
    b.resize(at + sizeof(T));
    detail::store_le(b.data() + at, v);
  }
  void str(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    b.insert(b.end(), s.begin(), s.end());
  }
  void bytes(const std::uint8_t* p, std::size_t n) { b.insert(b.end(), p, p + n); }
  void map(const std::map<std::string, std::string>& m) {
    Buf inner;
    for (const auto& [k, v] : m) {
      inner.str(k);
      inner.str(v);
    }
    put(static_cast<std::uint32_t>(inner.b.size()));
    bytes(inner.b.data(), inner.b.size());
  }
};

void append_record(std::vector<std::uint8_t>& out, std::uint8_t op, const Buf& content) {
  out.push_back(op);
  const std::size_t at = out.size();
  out.resize(at + 8);
  detail::store_le(out.data() + at, static_cast<std::uint64_t>(content.b.size()));
  out.insert(out.end(), content.b.begin(), content.b.end());
}
}  // namespace

struct McapWriter::Impl {
  struct Schema {
    std::uint16_t id;
    std::string name, encoding, data;
  };
  struct Channel {
    std::uint16_t id, schema;
    std::string topic, encoding;
    std::map<std::string, std::string> metadata;
  };
  struct ChunkIndex {
    std::uint64_t start, end, offset, length, index_length, compressed, uncompressed;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
  };

  std::string path, part;
  McapWriterOptions options;
  std::FILE* file = nullptr;
  std::uint64_t pos = 0;
  std::vector<Schema> schemas;
  std::vector<Channel> channels;
  std::vector<ChunkIndex> chunk_indexes;
  std::map<std::uint16_t, std::uint64_t> channel_counts;
  std::uint64_t messages = 0, first_time = 0, last_time = 0;
  // The open chunk.
  std::vector<std::uint8_t> chunk;
  std::uint64_t chunk_start = 0, chunk_end = 0;
  bool chunk_has_messages = false;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index;
  bool closed = false;

  void out(const std::uint8_t* p, std::size_t n) {
    if (std::fwrite(p, 1, n, file) != n) throw std::runtime_error(part + ": write failed (disk full?)");
    pos += n;
  }
  void out(const std::vector<std::uint8_t>& v) { out(v.data(), v.size()); }
  void record(std::uint8_t op, const Buf& content) {
    std::vector<std::uint8_t> r;
    append_record(r, op, content);
    out(r);
  }
  /// Schema / channel records go where the next message goes: the open chunk, or the file.
  void definition(std::uint8_t op, const Buf& content) {
    if (options.chunked)
      append_record(chunk, op, content);
    else
      record(op, content);
  }

  static Buf schema_record(const Schema& s) {
    Buf b;
    b.put(s.id);
    b.str(s.name);
    b.str(s.encoding);
    b.str(s.data);
    return b;
  }
  static Buf channel_record(const Channel& c) {
    Buf b;
    b.put(c.id);
    b.put(c.schema);
    b.str(c.topic);
    b.str(c.encoding);
    b.map(c.metadata);
    return b;
  }

  void flush_chunk() {
    if (chunk.empty()) return;
    std::vector<std::uint8_t> compressed;
    const std::vector<std::uint8_t>* records = &chunk;
    if (options.compression == "zstd") {
      compressed = detail::zstd_compress(chunk.data(), chunk.size());
      records = &compressed;
    } else if (options.compression == "lz4") {
      compressed = detail::lz4_compress(chunk.data(), chunk.size());
      records = &compressed;
    }
    Buf c;
    c.put(chunk_has_messages ? chunk_start : std::uint64_t{0});
    c.put(chunk_has_messages ? chunk_end : std::uint64_t{0});
    c.put(static_cast<std::uint64_t>(chunk.size()));
    c.put(static_cast<std::uint32_t>(crc32(0L, chunk.data(), static_cast<uInt>(chunk.size()))));
    c.str(options.compression);
    c.put(static_cast<std::uint64_t>(records->size()));
    c.bytes(records->data(), records->size());
    ChunkIndex idx{};
    idx.start = chunk_has_messages ? chunk_start : 0;
    idx.end = chunk_has_messages ? chunk_end : 0;
    idx.offset = pos;
    record(0x06, c);
    idx.length = pos - idx.offset;
    idx.compressed = records->size();
    idx.uncompressed = chunk.size();
    const std::uint64_t index_start = pos;
    if (options.message_indexes) {
      for (const auto& [channel, entries] : chunk_index) {
        Buf m;
        m.put(channel);
        m.put(static_cast<std::uint32_t>(entries.size() * 16));
        for (const auto& [t, o] : entries) {
          m.put(t);
          m.put(o);
        }
        idx.index_offsets[channel] = pos;
        record(0x07, m);
      }
    }
    idx.index_length = pos - index_start;
    chunk_indexes.push_back(idx);
    chunk.clear();
    chunk_index.clear();
    chunk_has_messages = false;
  }
};

McapWriter::McapWriter(const std::string& path, McapWriterOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.compression != "" && options.compression != "lz4" && options.compression != "zstd")
    throw std::invalid_argument("MCAP compression '" + options.compression + "': expected none, lz4 or zstd");
  impl_->path = path;
  impl_->part = path + ".part";
  impl_->options = std::move(options);
  impl_->file = std::fopen(impl_->part.c_str(), "wb");
  if (!impl_->file) throw InputError(impl_->part + ": cannot be written");
  impl_->out(kMagic, sizeof(kMagic));
  Buf h;
  h.str(impl_->options.profile);
  h.str("dloam");
  impl_->record(0x01, h);
}

McapWriter::~McapWriter() {
  if (!impl_ || impl_->closed) return;
  std::fclose(impl_->file);  // never closed: an unfinished file, not kept
  std::error_code ec;
  std::filesystem::remove(impl_->part, ec);
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding,
                                     const std::string& data) {
  Impl::Schema s{static_cast<std::uint16_t>(impl_->schemas.size() + 1), name, encoding, data};
  impl_->schemas.push_back(s);
  impl_->definition(0x03, Impl::schema_record(s));
  return s.id;
}

std::uint16_t McapWriter::add_channel(const std::string& topic, const std::string& message_encoding,
                                      std::uint16_t schema_id,
                                      const std::map<std::string, std::string>& metadata) {
  Impl::Channel c{static_cast<std::uint16_t>(impl_->channels.size()), schema_id, topic, message_encoding,
                  metadata};
  impl_->channels.push_back(c);
  impl_->definition(0x04, Impl::channel_record(c));
  return c.id;
}

void McapWriter::write(std::uint16_t channel_id, std::uint64_t log_time_ns, const std::uint8_t* data,
                       std::size_t size, std::uint64_t publish_time_ns, std::uint32_t sequence) {
  Impl& m = *impl_;
  if (channel_id >= m.channels.size()) throw std::invalid_argument("MCAP write: unknown channel");
  Buf rec;
  rec.put(channel_id);
  rec.put(sequence);
  rec.put(log_time_ns);
  rec.put(publish_time_ns ? publish_time_ns : log_time_ns);
  rec.bytes(data, size);
  if (m.messages == 0 || log_time_ns < m.first_time) m.first_time = log_time_ns;
  m.last_time = std::max(m.last_time, log_time_ns);
  ++m.messages;
  ++m.channel_counts[channel_id];
  if (!m.options.chunked) {
    m.record(0x05, rec);
    return;
  }
  if (!m.chunk_has_messages) {
    m.chunk_start = m.chunk_end = log_time_ns;
    m.chunk_has_messages = true;
  }
  m.chunk_start = std::min(m.chunk_start, log_time_ns);
  m.chunk_end = std::max(m.chunk_end, log_time_ns);
  m.chunk_index[channel_id].emplace_back(log_time_ns, m.chunk.size());
  append_record(m.chunk, 0x05, rec);
  if (m.chunk.size() >= m.options.chunk_size) m.flush_chunk();
}

void McapWriter::close() {
  Impl& m = *impl_;
  if (m.closed) return;
  m.closed = true;
  m.flush_chunk();
  Buf end;
  end.put(std::uint32_t{0});
  m.record(0x0F, end);
  std::uint64_t summary_start = 0, summary_offset_start = 0;
  if (m.options.summary) {
    summary_start = m.pos;
    std::vector<std::tuple<std::uint8_t, std::uint64_t, std::uint64_t>> groups;
    auto group = [&](std::uint8_t op, auto&& write_all) {
      const std::uint64_t start = m.pos;
      write_all();
      if (m.pos > start) groups.emplace_back(op, start, m.pos - start);
    };
    group(0x03, [&] {
      for (const auto& s : m.schemas) m.record(0x03, Impl::schema_record(s));
    });
    group(0x04, [&] {
      for (const auto& c : m.channels) m.record(0x04, Impl::channel_record(c));
    });
    group(0x08, [&] {
      for (const auto& c : m.chunk_indexes) {
        Buf b;
        b.put(c.start);
        b.put(c.end);
        b.put(c.offset);
        b.put(c.length);
        b.put(static_cast<std::uint32_t>(c.index_offsets.size() * 10));
        for (const auto& [channel, offset] : c.index_offsets) {
          b.put(channel);
          b.put(offset);
        }
        b.put(c.index_length);
        b.str(m.options.compression);
        b.put(c.compressed);
        b.put(c.uncompressed);
        m.record(0x08, b);
      }
    });
    group(0x0B, [&] {
      Buf s;
      s.put(m.messages);
      s.put(static_cast<std::uint16_t>(m.schemas.size()));
      s.put(static_cast<std::uint32_t>(m.channels.size()));
      s.put(std::uint32_t{0});  // attachments
      s.put(std::uint32_t{0});  // metadata
      s.put(static_cast<std::uint32_t>(m.chunk_indexes.size()));
      s.put(m.messages ? m.first_time : std::uint64_t{0});
      s.put(m.messages ? m.last_time : std::uint64_t{0});
      s.put(static_cast<std::uint32_t>(m.channel_counts.size() * 10));
      for (const auto& [channel, n] : m.channel_counts) {
        s.put(channel);
        s.put(n);
      }
      m.record(0x0B, s);
    });
    summary_offset_start = m.pos;
    for (const auto& [op, start, length] : groups) {
      Buf o;
      o.put(op);
      o.put(start);
      o.put(length);
      m.record(0x0E, o);
    }
  }
  Buf footer;
  footer.put(summary_start);
  footer.put(summary_offset_start);
  footer.put(std::uint32_t{0});  // summary CRC not computed
  m.record(0x02, footer);
  m.out(kMagic, sizeof(kMagic));
  const bool ok = std::fclose(m.file) == 0;
  m.file = nullptr;
  if (!ok) throw std::runtime_error(m.part + ": write failed");
  std::filesystem::rename(m.part, m.path);
}

}  // namespace dloam::io
