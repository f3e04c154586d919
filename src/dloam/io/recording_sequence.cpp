// Recordings as sequences (see recording_sequence.hpp).
#include "dloam/io/recording_sequence.hpp"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>

#include "dloam/drivers/registry.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/cdr.hpp"
#include "dloam/io/packet_messages.hpp"
#include "dloam/io/packet_sequence.hpp"
#include "dloam/io/pcap.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace fs = std::filesystem;
using detail::fail;

namespace {

/// How many datagrams of a capture are searched for the first data packet of a known LiDAR.
constexpr std::size_t kSearchDatagrams = 20000;

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

std::string decoders() { return join(drivers::available_vendors()); }

std::string ports_of(const PcapStats& stats) {
  std::string s;
  for (const auto& [port, n] : stats.ports)
    s += (s.empty() ? "" : ", ") + std::to_string(port) + ": " + std::to_string(n) + " datagrams";
  return s.empty() ? "no UDP datagrams" : s;
}

/// A file deleted with the last sequence that uses it (Ouster metadata taken from a bag topic).
struct TempFile {
  std::string path;
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

/// The driver options for `vendor`: calibration / metadata from the input, Ouster's JSON found
/// beside the recording (or given by `bag_metadata`) when none is given. `note` says which file.
drivers::DriverOptions driver_options(const InputOptions& in, drivers::Vendor vendor, const std::string& path,
                                      const std::string& bag_metadata, std::string& note) {
  drivers::DriverOptions o;
  o.scan = in.scan;
  // Refused here, naming the reason, before a driver opens it: missing, a FIFO (whose open would
  // wait for a writer), a device, or larger than any calibration file.
  for (const std::string* f : {&in.calibration, &in.metadata})
    if (!f->empty()) (void)read_file(*f, kMaxConfigFileBytes);
  if (vendor == drivers::Vendor::kOuster) {
    o.calibration = !in.metadata.empty() ? in.metadata : in.calibration;
    if (o.calibration.empty()) {
      o.calibration = !bag_metadata.empty() ? bag_metadata : ouster_metadata_beside(path);
      if (o.calibration.empty())
        fail(path,
             "holds Ouster packets, which cannot be decoded without the sensor's metadata JSON: no .json "
             "named like the recording beside it (nor a metadata topic); give it with --metadata FILE");
      note = bag_metadata.empty() ? "metadata " + o.calibration + " (found beside the recording)"
                                  : "metadata from the bag's metadata topic";
    } else {
      note = "metadata " + o.calibration;
    }
    return o;
  }
  if (!in.metadata.empty())
    fail(path, std::string("--metadata is the Ouster sensor JSON, but the recording holds ") +
                   drivers::vendor_name(vendor) + " packets: give a calibration with --calibration");
  o.calibration = in.calibration;
  if (!o.calibration.empty()) note = "calibration " + o.calibration;
  return o;
}

io::ScannerFactory factory(const drivers::DriverOptions& options, std::shared_ptr<TempFile> keep = nullptr) {
  return [options, keep](const std::vector<drivers::Packet>& first) {
    return drivers::make_scanner(options, first);
  };
}

// --- PointCloud2 topics ------------------------------------------------------------------------

class CloudSource : public ScanSource {
 public:
  CloudSource(std::shared_ptr<const Bag> bag, std::string topic)
      : bag_(std::move(bag)), topic_(std::move(topic)) {}
  [[nodiscard]] PointCloud read(std::size_t i) const override {
    const auto data = bag_->read(topic_, i);
    ConvertedCloud c = read_pointcloud2(data.data(), data.size(), bag_->where(topic_, i));
    dropped_ += c.dropped;
    return std::move(c.cloud);
  }
  [[nodiscard]] std::string describe() const override {
    return bag_->describe() + " " + bag_->path() + ", topic " + topic_ + " (" + kPointCloud2Type + "), " +
           std::to_string(bag_->message_count(topic_)) +
           " messages; NaN/Inf points dropped from is_dense=false clouds in the scans read: " +
           std::to_string(dropped_.load());
  }
  /// Header stamp of message i (s); the log time when the stamp is zero.
  [[nodiscard]] double stamp(std::size_t i) const {
    const auto data = bag_->read(topic_, i);
    CdrReader r(data.data(), data.size(), bag_->where(topic_, i));
    const std::int32_t sec = r.i32("header.stamp.sec");
    const std::uint32_t nsec = r.u32("header.stamp.nanosec");
    if (sec == 0 && nsec == 0) return 1e-9 * static_cast<double>(bag_->message_time_ns(topic_, i));
    return static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
  }

 private:
  std::shared_ptr<const Bag> bag_;
  std::string topic_;
  mutable std::atomic<std::size_t> dropped_{0};
};

/// The Ouster sensor JSON a bag carries on a std_msgs/msg/String topic named ".../metadata".
std::shared_ptr<TempFile> bag_metadata_file(const Bag& bag) {
  for (const auto& t : bag.topics()) {
    const bool named = t.name.size() >= 8 && t.name.compare(t.name.size() - 8, 8, "metadata") == 0;
    if (!named || t.type != "std_msgs/msg/String" || bag.message_count(t.name) == 0) continue;
    const auto data = bag.read(t.name, 0);
    CdrReader r(data.data(), data.size(), bag.where(t.name, 0));
    const std::string json = r.string("data");
    if (json.find('{') == std::string::npos) continue;
    auto file = std::make_shared<TempFile>();
    file->path =
        (fs::temp_directory_path() / ("dloam-metadata-" + std::to_string(::getpid()) + "-" +
                                      std::to_string(reinterpret_cast<std::uintptr_t>(file.get())) + ".json"))
            .string();
    std::ofstream(file->path) << json;
    return file;
  }
  return nullptr;
}

}  // namespace

std::string ouster_metadata_beside(const std::string& recording) {
  const fs::path p(recording);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::string stem = fs::is_directory(p) ? p.filename().string() : p.stem().string();
  std::error_code ec;
  while (!stem.empty()) {
    const fs::path candidate = dir / (stem + ".json");
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
    const std::size_t cut = stem.find_last_of("_-");
    if (cut == std::string::npos || cut == 0) break;
    stem.resize(cut);
  }
  return {};
}

Sequence open_pcap_sequence(const std::string& path, const InputOptions& in) {
  drivers::Vendor vendor = drivers::Vendor::kUnknown;
  std::uint16_t port = in.port;
  std::string first_where;
  {
    PcapReader reader(path);  // every port: find the data
    UdpDatagram d;
    std::size_t n = 0;
    while (n < kSearchDatagrams && reader.next(d)) {
      ++n;
      if (in.port != 0 && d.dst_port != in.port) continue;
      drivers::Packet p;
      p.data = d.payload.data();
      p.size = d.payload.size();
      p.stamp = d.time;
      p.port = d.dst_port;
      p.where = path + ": packet " + std::to_string(d.index) + " (record " + std::to_string(d.record) + ")";
      if (first_where.empty())
        first_where = p.where + ", " + std::to_string(p.size) + " bytes to port " + std::to_string(p.port);
      vendor = drivers::identify(p);
      if (vendor != drivers::Vendor::kUnknown) {
        port = d.dst_port;
        break;
      }
    }
    if (vendor == drivers::Vendor::kUnknown) {
      while (reader.next(d)) {  // the whole capture, for the message
      }
      const PcapStats& s = reader.stats();
      if (s.udp == 0) fail(path, "holds no UDP datagrams (" + s.describe() + ")");
      if (in.port != 0 && !s.ports.count(in.port))
        fail(path, "no UDP datagrams to port " + std::to_string(in.port) + " (" + ports_of(s) + ")");
      fail(path, std::string(n >= kSearchDatagrams ? "none of the first " + std::to_string(n)
                                                   : "none of the " + std::to_string(n)) +
                     " datagrams" + (in.port ? " to port " + std::to_string(in.port) : std::string()) +
                     " is a data packet of a known LiDAR (first: " + first_where + "; " + ports_of(s) +
                     "; decoders in this build: " + decoders() + ")");
    }
  }
  std::string note;
  const drivers::DriverOptions options = driver_options(in, vendor, path, {}, note);
  return open_packet_sequence(pcap_recording(path, port), factory(options), note);
}

std::string choose_bag_topic(const Bag& bag, const std::string& topic) {
  std::vector<std::string> clouds, packets, all;
  for (const auto& t : bag.topics()) {
    all.push_back(t.name + " (" + t.type + ")");
    if (t.type == kPointCloud2Type) clouds.push_back(t.name);
    if (is_packet_message_type(t.type)) packets.push_back(t.name);
  }
  if (!topic.empty()) {
    const BagTopic* t = bag.find_topic(topic);
    if (!t)
      fail(bag.path(), "no topic '" + topic + "' (PointCloud2 topics: " + join(clouds) +
                           "; packet topics: " + join(packets) + ")");
    if (t->type != kPointCloud2Type && !is_packet_message_type(t->type))
      fail(bag.path(), "topic '" + topic + "' has type " + t->type + ", expected " + kPointCloud2Type +
                           " or a packet message (" + join(packet_message_types()) + ")");
    return topic;
  }
  if (clouds.size() == 1) return clouds.front();
  if (clouds.size() > 1)
    fail(bag.path(), "has several PointCloud2 topics (" + join(clouds) + "): choose one with --topic");
  if (packets.size() > 1) {  // an Ouster bag: lidar and IMU packets of the same type
    std::vector<std::string> lidar;
    for (const auto& name : packets)
      if (name.find("imu") == std::string::npos) lidar.push_back(name);
    if (lidar.size() == 1) return lidar.front();
    fail(bag.path(), "has several packet topics (" + join(packets) + "): choose one with --topic");
  }
  if (packets.size() == 1) return packets.front();
  fail(bag.path(),
       std::string("no ") + kPointCloud2Type + " or raw-packet topic (topics: " + join(all) + ")");
}

Sequence open_bag2_sequence(const std::string& path, const InputOptions& in) {
  auto bag = std::make_shared<const Bag>(path);
  const std::string topic = choose_bag_topic(*bag, in.topic);
  const BagTopic& t = *bag->find_topic(topic);
  if (!t.encoding.empty() && t.encoding != "cdr")
    fail(path, "topic " + topic + " is serialized as '" + t.encoding + "'; only CDR is read");
  const std::size_t n = bag->message_count(topic);
  if (n == 0) fail(path, "topic " + topic + " has no messages");
  if (t.type == kPointCloud2Type) {
    auto source = std::make_shared<CloudSource>(bag, topic);
    Sequence seq;
    seq.dir = path;
    for (std::size_t i = 0; i < n; ++i) {
      seq.scan_files.push_back(bag->where(topic, i));
      seq.times.push_back(source->stamp(i));
    }
    seq.source = std::move(source);
    return seq;
  }
  auto recording = bag_packet_recording(bag, topic, t.type);
  // The vendor of the first packet a decoder claims among the first packets (those a scanner
  // is made from: first_packets()); the search stops there.
  drivers::Vendor vendor = drivers::Vendor::kUnknown;
  {
    auto stream = recording->open();
    drivers::Packet p;
    std::size_t packets = 0, bytes = 0;
    while (vendor == drivers::Vendor::kUnknown && packets < kFirstPackets && bytes < kFirstPacketBytes &&
           stream->next(p)) {
      ++packets;
      bytes += p.size;
      vendor = drivers::identify(p);
    }
    if (packets == 0) fail(path, "topic " + topic + " holds no packets");
  }
  std::shared_ptr<TempFile> metadata;
  if (vendor == drivers::Vendor::kOuster && in.metadata.empty() && in.calibration.empty())
    metadata = bag_metadata_file(*bag);
  std::string note;
  const drivers::DriverOptions options =
      driver_options(in, vendor, path, metadata ? metadata->path : "", note);
  return open_packet_sequence(std::move(recording), factory(options, metadata), note);
}

}  // namespace dloam::io
