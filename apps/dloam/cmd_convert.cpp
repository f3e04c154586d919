// `dloam convert RECORDING --out DIR`: the scans of any input (a capture or bag of raw packets,
// a bag of PointCloud2, a sequence folder) written as a sequence folder that other tools read:
// PCD files with a per-point `t` (s from the scan start) or KITTI .bin files, times.txt (s from
// the first scan), sensor.yaml (the recording's sensor model, a config file for `dloam run
// --config`) and recording.txt (the source and its first stamp); or as a ROS 2 bag of
// sensor_msgs/msg/PointCloud2 (MCAP or rosbag2 SQLite).
#include <fmt/core.h>

#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/mcap.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/pointcloud2_cdr.hpp"
#include "dloam/io/rosbag2_writer.hpp"
#include "input_args.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;

struct ConvertArgs {
  std::string input, out, format = "pcd", compression = "zstd", topic_out = "/points", frame = "lidar";
  InputArgs recording;
  long first = 0, count = -1;
};

/// A bag of PointCloud2 messages, MCAP or rosbag2 SQLite.
class CloudBagWriter {
 public:
  CloudBagWriter(const ConvertArgs& a) : format_(a.format), topic_(a.topic_out) {
    if (format_ == "mcap") {
      io::McapWriterOptions o;
      o.compression = a.compression == "none" ? "" : a.compression;
      mcap_ = std::make_unique<io::McapWriter>(a.out, o);
      channel_ = mcap_->add_channel(
          topic_, "cdr", mcap_->add_schema(io::kPointCloud2Type, "ros2msg", io::pointcloud2_definition()),
          {{"offered_qos_profiles", ""}});
    } else {
      db3_ = std::make_unique<io::Rosbag2Writer>(a.out);
      db3_->add_topic(topic_, io::kPointCloud2Type);
    }
  }
  void write(const PointCloud& cloud, double stamp, const std::string& frame) {
    const auto msg = io::encode_pointcloud2(cloud, stamp, frame);
    const auto ns = static_cast<std::int64_t>(std::llround(stamp * 1e9));
    if (mcap_)
      mcap_->write(channel_, static_cast<std::uint64_t>(ns), msg.data(), msg.size());
    else
      db3_->write(topic_, ns, msg.data(), msg.size());
  }
  void close() {
    if (mcap_) mcap_->close();
    if (db3_) db3_->close();
  }

 private:
  std::string format_, topic_;
  std::unique_ptr<io::McapWriter> mcap_;
  std::unique_ptr<io::Rosbag2Writer> db3_;
  std::uint16_t channel_ = 0;
};

void run_convert(const ConvertArgs& a) {
  const InputConfig input = apply_input_args(InputConfig{}, a.recording);
  const io::Sequence seq = io::open_sequence(a.input, io::input_options(input));
  const std::size_t first = static_cast<std::size_t>(std::max(0L, a.first));
  if (first >= seq.size())
    throw InputError(fmt::format("{}: --first {} but it has {} scans", a.input, first, seq.size()));
  const std::size_t last =
      a.count < 0 ? seq.size() : std::min(seq.size(), first + static_cast<std::size_t>(a.count));
  const bool bag = a.format == "mcap" || a.format == "db3";
  const double rate = seq.sensor ? seq.sensor->scan_rate_hz : 10.0;
  const double t0 = seq.times.empty() ? 0.0 : seq.times[first];
  std::unique_ptr<CloudBagWriter> writer;
  if (bag) {
    if (fs::exists(a.out)) throw InputError(a.out + ": exists already");
    writer = std::make_unique<CloudBagWriter>(a);
  } else {
    fs::create_directories(a.format == "kitti" ? a.out + "/velodyne" : a.out);
  }
  fmt::print("dloam convert: {} scans of {} -> {} ({})\n", last - first, a.input, a.out, a.format);
  Progress progress("convert", last - first);
  std::vector<double> times;
  for (std::size_t i = first; i < last; ++i) {
    PointCloud cloud = seq.read_scan(i);
    const double stamp = i < seq.times.size() ? seq.times[i] : 0.1 * static_cast<double>(i);
    const std::string name = io::scan_name(i - first);
    if (bag) {
      writer->write(cloud, stamp, a.frame);
    } else if (a.format == "kitti") {
      io::write_kitti_bin(a.out + "/velodyne/" + name + ".bin", cloud);
    } else {
      for (float& t : cloud.time)
        t = static_cast<float>(t / rate);  // sweep fraction -> s from the scan start
      io::write_pcd(a.out + "/" + name + ".pcd", cloud, io::Encoding::kBinary, "t");
    }
    times.push_back(stamp - t0);
    progress.update(i - first + 1);
  }
  if (bag) {
    writer->close();
    fmt::print("wrote {} ({} PointCloud2 messages on {})\n", a.out, last - first, a.topic_out);
    return;
  }
  io::write_times(a.out + "/times.txt", times);
  if (seq.sensor) {
    PipelineConfig cfg;
    cfg.sensor = *seq.sensor;
    io::write_atomic(a.out + "/sensor.yaml", [&](std::ostream& o) { o << io::dump_config(cfg, "sensor"); });
  }
  io::write_atomic(a.out + "/recording.txt", [&](std::ostream& o) {
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.9f", t0);
    o << "source: " << a.input << "\nfirst_scan_stamp_s: " << stamp << "\nscans: " << times.size()
      << "\nread: " << (seq.source ? seq.source->describe() : std::string("sequence folder")) << '\n';
  });
  fmt::print("wrote {}/{} ({} scans), times.txt, {}recording.txt\n", a.out,
             a.format == "kitti" ? "velodyne/*.bin" : "*.pcd", times.size(),
             seq.sensor ? "sensor.yaml, " : "");
}

}  // namespace

void register_convert(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  auto* cmd =
      app.add_subcommand("convert", "write the scans of a recording as a sequence folder or a ROS 2 bag");
  cmd->add_option("RECORDING", args->input,
                  "capture (.pcap, .pcapng), bag (.bag, .db3, .mcap, rosbag2 folder) or sequence folder")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out,-o", args->out, "output folder (kitti, pcd, db3) or file (mcap)")->required();
  cmd->add_option("--format", args->format,
                  "pcd: NNNNNN.pcd with a per-point t (s from the scan start); kitti: velodyne/NNNNNN.bin; "
                  "mcap / db3: a ROS 2 bag of sensor_msgs/msg/PointCloud2")
      ->check(CLI::IsMember({"pcd", "kitti", "mcap", "db3"}));
  cmd->add_option("--compression", args->compression, "mcap: chunk compression none, lz4 or zstd")
      ->check(CLI::IsMember({"none", "lz4", "zstd"}));
  cmd->add_option("--out-topic", args->topic_out, "mcap / db3: the topic written");
  cmd->add_option("--frame-id", args->frame, "mcap / db3: the header frame_id written");
  add_input_options(cmd, args->recording);
  cmd->add_option("--first", args->first, "first scan index");
  cmd->add_option("--count", args->count, "number of scans (default: all)");
  cmd->footer(
      "The folder formats also get times.txt (scan start times, s from the first scan), sensor.yaml (the\n"
      "recording's sensor model as a config file: dloam run DIR --config DIR/sensor.yaml) and "
      "recording.txt.\n"
      "KITTI .bin files carry no per-point time (there is no standard for one); use pcd to keep it.\n"
      "Examples:\n"
      "  dloam convert vlp16.pcap --out vlp16_pcd\n"
      "  dloam convert os1.pcap --metadata os1.json --format kitti --out os1_kitti\n"
      "  dloam convert ../shared/data/kitti-raw-0005 --format mcap --compression lz4 --out kitti.mcap");
  cmd->callback([args] { run_convert(*args); });
}

}  // namespace dloam::app
