// Raw-packet recordings as sequences (see packet_sequence.hpp).
#include "dloam/io/packet_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>

#include "dloam/io/bag.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/pcap.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;

namespace {

// --- pcap -------------------------------------------------------------------------------------

struct PcapShared {
  std::string path;
  std::uint16_t port = 0;
  std::mutex mutex;
  PcapStats stats;  ///< of the longest pass so far (the indexing pass reads everything)
};

class PcapStream : public PacketStream {
 public:
  PcapStream(std::shared_ptr<PcapShared> shared, const PacketCheckpoint* from)
      : shared_(std::move(shared)), reader_(shared_->path, options(shared_->port)) {
    if (from) reader_.seek({static_cast<long>(from->a), static_cast<std::size_t>(from->b), from->packet});
  }
  bool next(drivers::Packet& p) override {
    if (!reader_.next(d_)) {
      std::lock_guard<std::mutex> lock(shared_->mutex);
      if (reader_.stats().records >= shared_->stats.records) shared_->stats = reader_.stats();
      return false;
    }
    p.data = d_.payload.data();
    p.size = d_.payload.size();
    p.stamp = d_.time;
    p.port = d_.dst_port;
    // Assigned in place: the string keeps its buffer from packet to packet.
    p.where.assign(shared_->path).append(": packet ").append(std::to_string(d_.index));
    p.where.append(" (record ").append(std::to_string(d_.record)).append(")");
    return true;
  }
  [[nodiscard]] std::optional<PacketCheckpoint> checkpoint() const override {
    const auto pos = reader_.position();
    if (!pos) return std::nullopt;
    return PacketCheckpoint{static_cast<std::uint64_t>(pos->offset), pos->record, pos->datagram};
  }

 private:
  static PcapOptions options(std::uint16_t port) {
    PcapOptions o;
    o.port = port;
    return o;
  }
  std::shared_ptr<PcapShared> shared_;
  PcapReader reader_;
  UdpDatagram d_;
};

class PcapRecording : public PacketRecording {
 public:
  PcapRecording(const std::string& path, std::uint16_t port) : shared_(std::make_shared<PcapShared>()) {
    shared_->path = path;
    shared_->port = port;
  }
  [[nodiscard]] std::unique_ptr<PacketStream> open(const PacketCheckpoint* from) const override {
    return std::make_unique<PcapStream>(shared_, from);
  }
  [[nodiscard]] std::string name() const override { return shared_->path; }
  [[nodiscard]] std::string describe() const override {
    std::lock_guard<std::mutex> lock(shared_->mutex);
    return "capture " + shared_->path + (shared_->port ? ", UDP port " + std::to_string(shared_->port) : "") +
           ": " + shared_->stats.describe();
  }

 private:
  std::shared_ptr<PcapShared> shared_;
};

// --- ROS 2 bag packet topics ---------------------------------------------------------------------

class BagPacketStream : public PacketStream {
 public:
  BagPacketStream(std::shared_ptr<const Bag> bag, std::string topic, std::string type,
                  const PacketCheckpoint* from)
      : bag_(std::move(bag)),
        topic_(std::move(topic)),
        type_(std::move(type)),
        count_(bag_->message_count(topic_)) {
    if (from) {
      message_ = static_cast<std::size_t>(from->a);
      packet_ = from->packet;
      if (message_ < count_) load(message_);
      slot_ = static_cast<std::size_t>(from->b);
    }
  }
  bool next(drivers::Packet& p) override {
    while (!loaded_ || slot_ >= msg_.packets.size()) {
      const std::size_t k = loaded_ ? message_ + 1 : message_;
      if (k >= count_) return false;
      load(k);
      slot_ = 0;
    }
    const PacketSlice& s = msg_.packets[slot_];
    p.data = data_.data() + s.offset;
    p.size = s.size;
    p.stamp = s.stamp != 0.0 ? s.stamp : msg_.stamp;
    p.port = 0;
    // Assigned in place: the string keeps its buffer from packet to packet.
    p.where.assign(where_).append(", packet ").append(std::to_string(slot_));
    p.where.append(" (packet ").append(std::to_string(packet_)).append(" of the topic)");
    ++slot_;
    ++packet_;
    return true;
  }
  [[nodiscard]] std::optional<PacketCheckpoint> checkpoint() const override {
    if (!loaded_) return PacketCheckpoint{message_, 0, packet_};
    return PacketCheckpoint{message_, slot_, packet_};
  }

 private:
  void load(std::size_t k) {
    data_ = bag_->read(topic_, k);
    msg_ = decode_packet_message(type_, data_.data(), data_.size(),
                                 1e-9 * static_cast<double>(bag_->message_time_ns(topic_, k)),
                                 bag_->where(topic_, k));
    message_ = k;
    where_ = bag_->where(topic_, k);
    loaded_ = true;
  }
  std::shared_ptr<const Bag> bag_;
  std::string topic_, type_;
  std::size_t count_ = 0, message_ = 0, slot_ = 0, packet_ = 0;
  bool loaded_ = false;
  std::vector<std::uint8_t> data_;
  PacketMessage msg_;
  std::string where_;  ///< the message's
};

class BagPacketRecording : public PacketRecording {
 public:
  BagPacketRecording(std::shared_ptr<const Bag> bag, std::string topic, std::string type)
      : bag_(std::move(bag)), topic_(std::move(topic)), type_(std::move(type)) {}
  [[nodiscard]] std::unique_ptr<PacketStream> open(const PacketCheckpoint* from) const override {
    return std::make_unique<BagPacketStream>(bag_, topic_, type_, from);
  }
  [[nodiscard]] std::string name() const override { return bag_->path() + ": topic " + topic_; }
  [[nodiscard]] std::string describe() const override {
    return bag_->describe() + " " + bag_->path() + ", topic " + topic_ + " (" + type_ + "), " +
           std::to_string(bag_->message_count(topic_)) + " messages";
  }

 private:
  std::shared_ptr<const Bag> bag_;
  std::string topic_, type_;
};

// --- the sequence ---------------------------------------------------------------------------------

/// What the indexing pass learnt about one scan.
struct ScanEntry {
  double start = 0.0, end = 0.0;
  std::size_t points = 0;
  bool complete = true;
  std::size_t emitted_at = 0;  ///< packets fed when the scan came out (all of them: finish())
  bool at_finish = false;
  std::optional<PacketCheckpoint> resume_after;  ///< a clean position at or before its emission
};

bool same_scan(const drivers::Scan& s, const ScanEntry& e) {
  return s.start == e.start && s.size() == e.points;
}

class PacketSource : public ScanSource {
 public:
  /// `prototype`: a fresh scanner to restart() for each decoding session; without one (a
  /// scanner that cannot restart), `factory` makes them from `first`.
  PacketSource(std::shared_ptr<PacketRecording> recording, ScannerFactory factory,
               std::unique_ptr<drivers::Scanner> prototype, FirstPackets first,
               std::vector<ScanEntry> entries, std::vector<std::size_t> kept, double rate,
               std::string scanner_line, std::size_t packets)
      : recording_(std::move(recording)),
        factory_(std::move(factory)),
        prototype_(std::move(prototype)),
        first_(std::move(first)),
        entries_(std::move(entries)),
        kept_(std::move(kept)),
        rate_(rate),
        scanner_line_(std::move(scanner_line)),
        packets_(packets) {}

  [[nodiscard]] PointCloud read(std::size_t i) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::size_t e = kept_.at(i);
    drivers::Scan scan;
    if (!continue_session(e, scan)) {
      start_session(e >= 2 ? entries_[e - 2].resume_after : std::nullopt);
      if (!continue_session(e, scan)) {
        start_session(std::nullopt);  // from the start: slow, but the state is the indexing pass's
        if (!continue_session(e, scan))
          fail(recording_->name(),
               "scan " + std::to_string(i) + " does not decode again as it did when indexed");
      }
    }
    return to_point_cloud(std::move(scan), rate_);
  }

  [[nodiscard]] std::string describe() const override {
    const std::size_t left_out = entries_.size() - kept_.size();
    return recording_->describe() + "; " + std::to_string(packets_) + " packets; " + scanner_line_ + "; " +
           std::to_string(kept_.size()) + " scans" +
           (left_out ? " (" + std::to_string(left_out) + " incomplete rotations left out)" : std::string());
  }

 private:
  struct Session {
    std::unique_ptr<PacketStream> stream;
    std::unique_ptr<drivers::Scanner> scanner;
    std::deque<drivers::Scan> pending;
    std::size_t fed = 0;  ///< packets fed (global index of the next packet)
    bool finished = false;
  };

  void start_session(const std::optional<PacketCheckpoint>& from) const {
    session_ = std::make_unique<Session>();
    session_->stream = recording_->open(from ? &*from : nullptr);
    session_->scanner = prototype_ ? prototype_->restart() : nullptr;
    if (!session_->scanner) session_->scanner = factory_(first_.packets);
    session_->fed = from ? from->packet : 0;
  }

  /// Feeds the session until entry e's scan comes out (true) or cannot any more (false).
  bool continue_session(std::size_t e, drivers::Scan& out) const {
    if (!session_) return false;
    Session& s = *session_;
    const ScanEntry& want = entries_[e];
    std::vector<drivers::Scan> done;
    drivers::Packet p;
    for (;;) {
      while (!s.pending.empty()) {
        drivers::Scan scan = std::move(s.pending.front());
        s.pending.pop_front();
        if (same_scan(scan, want)) {
          out = std::move(scan);
          return true;
        }
      }
      if (s.finished || (!want.at_finish && s.fed >= want.emitted_at)) return false;
      if (s.stream->next(p)) {
        s.scanner->add(p, done);
        ++s.fed;
      } else {
        s.scanner->finish(done);
        s.finished = true;
      }
      for (auto& scan : done) s.pending.push_back(std::move(scan));
      done.clear();
    }
  }

  std::shared_ptr<PacketRecording> recording_;
  ScannerFactory factory_;
  std::unique_ptr<drivers::Scanner> prototype_;
  FirstPackets first_;
  std::vector<ScanEntry> entries_;
  std::vector<std::size_t> kept_;
  double rate_;
  std::string scanner_line_;
  std::size_t packets_;
  mutable std::mutex mutex_;
  mutable std::unique_ptr<Session> session_;
};

}  // namespace

std::shared_ptr<PacketRecording> pcap_recording(const std::string& path, std::uint16_t port) {
  return std::make_shared<PcapRecording>(path, port);
}

std::shared_ptr<PacketRecording> bag_packet_recording(std::shared_ptr<const Bag> bag,
                                                      const std::string& topic, const std::string& type) {
  return std::make_shared<BagPacketRecording>(std::move(bag), topic, type);
}

FirstPackets first_packets(const PacketRecording& recording, std::size_t max_packets, std::size_t max_bytes) {
  auto stream = recording.open();
  return first_packets(*stream, max_packets, max_bytes);
}

FirstPackets first_packets(PacketStream& stream, std::size_t max_packets, std::size_t max_bytes) {
  FirstPackets out;
  drivers::Packet p;
  std::size_t bytes = 0;
  std::vector<drivers::Packet> meta;
  while (out.bytes.size() < max_packets && bytes < max_bytes && stream.next(p)) {
    out.bytes.emplace_back(p.data, p.data + p.size);
    out.after.push_back(stream.checkpoint());
    bytes += p.size;
    meta.push_back(p);
  }
  for (std::size_t k = 0; k < meta.size(); ++k) {
    drivers::Packet q = meta[k];
    q.data = out.bytes[k].data();
    out.packets.push_back(std::move(q));
  }
  return out;
}

namespace {

/// The per-point sweep fractions of a scan (empty without per-point stamps).
std::vector<float> sweep_fractions(const drivers::Scan& scan, double scan_rate_hz) {
  std::vector<float> time;
  if (scan.stamps.size() != scan.xyz.size()) return time;
  const float below_one = std::nextafter(1.0f, 0.0f);
  time.resize(scan.xyz.size());
  for (std::size_t k = 0; k < scan.xyz.size(); ++k) {
    const double f = (scan.stamps[k] - scan.start) * scan_rate_hz;
    time[k] = std::clamp(static_cast<float>(f), 0.0f, below_one);
  }
  return time;
}

}  // namespace

PointCloud to_point_cloud(const drivers::Scan& scan, double scan_rate_hz) {
  PointCloud cloud;
  cloud.xyz = scan.xyz;
  if (scan.intensity.size() == scan.xyz.size()) cloud.intensity = scan.intensity;
  cloud.time = sweep_fractions(scan, scan_rate_hz);
  return cloud;
}

PointCloud to_point_cloud(drivers::Scan&& scan, double scan_rate_hz) {
  PointCloud cloud;
  cloud.time = sweep_fractions(scan, scan_rate_hz);
  if (scan.intensity.size() == scan.xyz.size()) cloud.intensity = std::move(scan.intensity);
  cloud.xyz = std::move(scan.xyz);
  return cloud;
}

Sequence open_packet_sequence(std::shared_ptr<PacketRecording> recording, ScannerFactory make_scanner,
                              const std::string& note) {
  // One pass: the first packets (kept, to make the scanner from) are fed from their copies, the
  // rest straight from the stream.
  auto stream = recording->open();
  std::optional<PacketCheckpoint> clean = stream->checkpoint();
  FirstPackets first = first_packets(*stream);
  if (first.packets.empty()) {
    const std::string what = recording->describe();
    fail(recording->name(), "holds no packets (" + what + ")");
  }
  std::unique_ptr<drivers::Scanner> scanner = make_scanner(first.packets);
  // The index needs the scans' outlines only; their points are decoded when read.
  const bool outlined = scanner->outline_only(true);
  std::vector<ScanEntry> entries;
  std::vector<drivers::Scan> done;
  drivers::Packet p;
  std::size_t fed = 0;
  auto record = [&](bool at_finish) {
    for (const auto& s : done)
      entries.push_back(
          {s.start, s.end, outlined ? s.outline_points : s.size(), s.complete, fed, at_finish, clean});
    done.clear();
  };
  auto feed = [&](const drivers::Packet& packet, const std::optional<PacketCheckpoint>& after) {
    scanner->add(packet, done);
    ++fed;
    if (after) clean = after;
    record(false);
  };
  for (std::size_t k = 0; k < first.packets.size(); ++k) feed(first.packets[k], first.after[k]);
  while (stream->next(p)) feed(p, stream->checkpoint());
  scanner->finish(done);
  record(true);
  std::vector<std::size_t> kept;
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (entries[e].complete && entries[e].points > 0) kept.push_back(e);
  if (kept.empty())
    for (std::size_t e = 0; e < entries.size(); ++e)
      if (entries[e].points > 0) kept.push_back(e);
  if (kept.empty())
    fail(recording->name(),
         std::to_string(fed) + " packets gave no scan with points (" + scanner->describe() + ")");

  Sequence seq;
  seq.dir = recording->name();
  seq.sensor = scanner->sensor();
  const double rate = seq.sensor->scan_rate_hz > 0 ? seq.sensor->scan_rate_hz : 10.0;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    seq.scan_files.push_back(recording->name() + ": scan " + std::to_string(i));
    seq.times.push_back(entries[kept[i]].start);
  }
  // Decoding sessions restart a scanner that shares the index scanner's tables (an Ouster
  // scanner's xyz lookup table); only a scanner that cannot restart is made again from the first
  // packets, which are then kept.
  std::unique_ptr<drivers::Scanner> prototype = scanner->restart();
  if (prototype) first = FirstPackets{};
  seq.source =
      std::make_shared<PacketSource>(std::move(recording), std::move(make_scanner), std::move(prototype),
                                     std::move(first), std::move(entries), std::move(kept), rate,
                                     scanner->describe() + (note.empty() ? "" : "; " + note), fed);
  return seq;
}

}  // namespace dloam::io
