// ROS 2 bags (see bag.hpp): the files of a rosbag2 folder merged into one time-ordered view.
#include "dloam/io/bag.hpp"

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "dloam/core/types.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/compression.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

namespace fs = std::filesystem;
using detail::fail;

namespace {

/// What a file is, from its first bytes (the extension may lie).
enum class Storage { kSqlite, kMcap, kUnknown };
Storage sniff(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[16] = {0};
  in.read(head, sizeof(head));
  const std::string h(head, static_cast<std::size_t>(in.gcount()));
  if (h.rfind(std::string("SQLite format 3\0", 16), 0) == 0) return Storage::kSqlite;
  if (h.rfind("\x89MCAP0\r\n", 0) == 0) return Storage::kMcap;
  return Storage::kUnknown;
}

std::unique_ptr<bag_detail::BagFile> open_storage_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail(path, "bag file not found");
  if (fs::file_size(path, ec) == 0) fail(path, "empty file (0 bytes), not a bag");
  switch (sniff(path)) {
    case Storage::kSqlite:
      return bag_detail::open_sqlite_file(path);
    case Storage::kMcap:
      return bag_detail::open_mcap_file(path);
    case Storage::kUnknown:
      break;
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".db3")
    fail(path, "not a readable rosbag2 SQLite file (no SQLite header: damaged or another format)");
  if (ext == ".mcap") fail(path, "not an MCAP file (no MCAP magic at the start)");
  fail(path, "neither a rosbag2 SQLite (.db3) nor an MCAP file");
}

std::string unique_temp_path(const std::string& name) {
  static std::atomic<int> counter{0};
  return (fs::temp_directory_path() /
          ("dloam-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + name))
      .string();
}

struct Metadata {
  std::vector<std::string> files;  ///< relative paths
  std::string compression_format, compression_mode;
};

Metadata read_metadata(const std::string& yaml_path) {
  Metadata m;
  try {
    const YAML::Node root = YAML::Load(read_file(yaml_path, kMaxConfigFileBytes));
    const YAML::Node info = root["rosbag2_bagfile_information"];
    if (!info || !info.IsMap())
      fail(yaml_path, "no rosbag2_bagfile_information map: not a rosbag2 metadata file");
    if (const YAML::Node paths = info["relative_file_paths"]; paths && paths.IsSequence())
      for (const auto& p : paths) m.files.push_back(p.as<std::string>());
    if (m.files.empty())
      if (const YAML::Node files = info["files"]; files && files.IsSequence())
        for (const auto& f : files)
          if (f["path"]) m.files.push_back(f["path"].as<std::string>());
    if (info["compression_format"]) m.compression_format = info["compression_format"].as<std::string>();
    if (info["compression_mode"]) m.compression_mode = info["compression_mode"].as<std::string>();
  } catch (const YAML::Exception& e) {
    fail(yaml_path, std::string("not a readable rosbag2 metadata file (") + e.what() + ")");
  }
  if (!m.compression_format.empty() && m.compression_format != "zstd")
    fail(yaml_path, "compression_format '" + m.compression_format + "' is not supported (zstd is)");
  return m;
}

}  // namespace

Bag::Bag(const std::string& path) : path_(path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "bag not found");
  if (fs::is_directory(path, ec)) {
    const std::string yaml = (fs::path(path) / "metadata.yaml").string();
    if (!fs::exists(yaml, ec)) fail(path, "is a folder without metadata.yaml: not a rosbag2 bag");
    const Metadata m = read_metadata(yaml);
    std::vector<std::string> files = m.files;
    if (files.empty()) {  // metadata without a file list: the storage files of the folder
      for (const auto& e : fs::directory_iterator(path))
        if (e.path().extension() == ".db3" || e.path().extension() == ".mcap")
          files.push_back(e.path().filename());
      std::sort(files.begin(), files.end());
    }
    if (files.empty()) fail(yaml, "lists no storage files and the folder holds no .db3 / .mcap file");
    compressed_messages_ = m.compression_format == "zstd" && m.compression_mode == "MESSAGE";
    const bool file_mode = m.compression_format == "zstd" && m.compression_mode == "FILE";
    for (const auto& rel : files) {
      std::string file = (fs::path(path) / rel).string();
      if (!fs::exists(file, ec)) fail(yaml, "lists " + rel + ", which is not in the folder");
      if (file_mode || fs::path(file).extension() == ".zstd") {
        const std::string plain = unique_temp_path(fs::path(rel).stem().string());
        temp_files_.push_back(plain);
        detail::zstd_decompress_file(file, plain);
        file = plain;
      }
      files_.push_back(open_storage_file(file));
    }
  } else {
    files_.push_back(open_storage_file(path));
  }
  std::map<std::string, BagTopic> merged;
  for (const auto& f : files_) {
    for (const BagTopic& t : f->topics()) {
      auto [it, fresh] = merged.emplace(t.name, t);
      if (fresh) continue;
      if (it->second.type != t.type)
        fail(f->path(), "topic " + t.name + " has type " + t.type + " here but " + it->second.type + " in " +
                            files_.front()->path());
      it->second.messages += t.messages;
    }
  }
  for (auto& [name, t] : merged) topics_.push_back(t);
}

Bag::~Bag() {
  files_.clear();
  std::error_code ec;
  for (const auto& f : temp_files_) fs::remove(f, ec);
}

const BagTopic* Bag::find_topic(const std::string& name) const {
  for (const auto& t : topics_)
    if (t.name == name) return &t;
  return nullptr;
}

const std::vector<Bag::Entry>& Bag::index(const std::string& topic) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = indexes_.find(topic);
  if (it != indexes_.end()) return it->second;
  if (!find_topic(topic)) fail(path_, "no topic '" + topic + "'");
  std::vector<Entry> entries;
  for (std::size_t f = 0; f < files_.size(); ++f)
    for (const auto& ref : files_[f]->index(topic)) entries.push_back({ref.time_ns, f, ref.locator});
  // Files in order, each in time order: a stable sort by time keeps the file order of ties.
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.time_ns < b.time_ns; });
  return indexes_.emplace(topic, std::move(entries)).first->second;
}

std::size_t Bag::message_count(const std::string& topic) const { return index(topic).size(); }

std::int64_t Bag::message_time_ns(const std::string& topic, std::size_t k) const {
  const auto& idx = index(topic);
  if (k >= idx.size()) fail(where(topic, k), "no such message (" + std::to_string(idx.size()) + " messages)");
  return idx[k].time_ns;
}

std::vector<std::uint8_t> Bag::read(const std::string& topic, std::size_t k) const {
  const auto& idx = index(topic);
  const std::string name = where(topic, k);
  if (k >= idx.size()) fail(name, "no such message (" + std::to_string(idx.size()) + " messages)");
  std::vector<std::uint8_t> data;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    data = files_[idx[k].file]->read({idx[k].time_ns, idx[k].locator}, name);
  }
  if (compressed_messages_) return detail::zstd_decompress(data.data(), data.size(), 0, name);
  return data;
}

std::string Bag::where(const std::string& topic, std::size_t k) const {
  return path_ + ": topic " + topic + ", message " + std::to_string(k);
}

std::string Bag::describe() const {
  std::string s = files_.empty() ? "bag" : files_.front()->format();
  if (files_.size() > 1) s += ", " + std::to_string(files_.size()) + " files";
  if (compressed_messages_) s += ", zstd per message";
  if (!temp_files_.empty()) s += ", zstd per file";
  return s;
}

}  // namespace dloam::io
