// rosbag2 bag folder writer (see rosbag2_writer.hpp), over libsqlite3 and yaml-cpp.
#include "dloam/io/rosbag2_writer.hpp"

#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "dloam/core/types.hpp"

namespace dloam::io {

namespace fs = std::filesystem;

struct Rosbag2Writer::Impl {
  struct Topic {
    std::int64_t id;
    std::string type, serialization;
    std::size_t messages = 0;
  };
  std::string dir, part, name;
  sqlite3* db = nullptr;
  sqlite3_stmt* insert = nullptr;
  std::map<std::string, Topic> topics;
  std::int64_t first = std::numeric_limits<std::int64_t>::max(),
               last = std::numeric_limits<std::int64_t>::min();
  std::size_t messages = 0;
  bool closed = false;

  void exec(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : "?";
      sqlite3_free(err);
      throw std::runtime_error(part + ": sqlite: " + msg);
    }
  }
  void check(int rc, const char* what) {
    if (rc != SQLITE_OK && rc != SQLITE_DONE)
      throw std::runtime_error(part + ": sqlite " + what + ": " + sqlite3_errmsg(db));
  }
};

Rosbag2Writer::Rosbag2Writer(const std::string& dir) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.dir = dir;
  m.part = dir + ".part";
  m.name = fs::path(dir).filename().string();
  if (m.name.empty()) m.name = fs::path(dir).parent_path().filename().string();
  std::error_code ec;
  if (fs::exists(dir, ec)) throw InputError(dir + ": exists already (a bag is written into a new folder)");
  fs::remove_all(m.part, ec);
  fs::create_directories(m.part);
  const std::string db3 = (fs::path(m.part) / (m.name + "_0.db3")).string();
  if (sqlite3_open(db3.c_str(), &m.db) != SQLITE_OK) throw InputError(db3 + ": cannot be created");
  m.exec("PRAGMA journal_mode = MEMORY; PRAGMA synchronous = OFF;");
  m.exec(
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);"
      "INSERT INTO schema VALUES (3, 'humble');"
      "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT NOT "
      "NULL);"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
      "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL, "
      "data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "BEGIN TRANSACTION;");
  m.check(sqlite3_prepare_v2(m.db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1,
                             &m.insert, nullptr),
          "prepare");
}

Rosbag2Writer::~Rosbag2Writer() {
  if (!impl_ || impl_->closed) return;
  sqlite3_finalize(impl_->insert);
  sqlite3_close(impl_->db);
  std::error_code ec;
  fs::remove_all(impl_->part, ec);
}

void Rosbag2Writer::add_topic(const std::string& name, const std::string& type,
                              const std::string& serialization) {
  Impl& m = *impl_;
  if (m.topics.count(name)) throw std::invalid_argument("rosbag2 writer: topic " + name + " added twice");
  const auto id = static_cast<std::int64_t>(m.topics.size() + 1);
  sqlite3_stmt* s = nullptr;
  m.check(sqlite3_prepare_v2(m.db, "INSERT INTO topics VALUES (?, ?, ?, ?, '')", -1, &s, nullptr), "prepare");
  sqlite3_bind_int64(s, 1, id);
  sqlite3_bind_text(s, 2, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s, 3, type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s, 4, serialization.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  m.check(rc, "insert topic");
  m.topics[name] = {id, type, serialization, 0};
}

void Rosbag2Writer::write(const std::string& topic, std::int64_t time_ns, const std::uint8_t* data,
                          std::size_t size) {
  Impl& m = *impl_;
  const auto it = m.topics.find(topic);
  if (it == m.topics.end()) throw std::invalid_argument("rosbag2 writer: unknown topic " + topic);
  sqlite3_reset(m.insert);
  sqlite3_bind_int64(m.insert, 1, it->second.id);
  sqlite3_bind_int64(m.insert, 2, time_ns);
  sqlite3_bind_blob64(m.insert, 3, data, size, SQLITE_STATIC);
  m.check(sqlite3_step(m.insert), "insert message");
  ++it->second.messages;
  ++m.messages;
  m.first = std::min(m.first, time_ns);
  m.last = std::max(m.last, time_ns);
}

void Rosbag2Writer::close() {
  Impl& m = *impl_;
  if (m.closed) return;
  m.exec("COMMIT;");
  sqlite3_finalize(m.insert);
  m.insert = nullptr;
  if (sqlite3_close(m.db) != SQLITE_OK) throw std::runtime_error(m.part + ": sqlite close failed");
  m.db = nullptr;
  m.closed = true;
  const std::int64_t start = m.messages ? m.first : 0, duration = m.messages ? m.last - m.first : 0;
  const std::string file = m.name + "_0.db3";
  YAML::Emitter y;
  y << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "version" << YAML::Value << 5;
  y << YAML::Key << "storage_identifier" << YAML::Value << "sqlite3";
  y << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds" << YAML::Value
    << duration << YAML::EndMap;
  y << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch"
    << YAML::Value << start << YAML::EndMap;
  y << YAML::Key << "message_count" << YAML::Value << m.messages;
  y << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const auto& [name, t] : m.topics) {
    y << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
    y << YAML::Key << "name" << YAML::Value << name << YAML::Key << "type" << YAML::Value << t.type;
    y << YAML::Key << "serialization_format" << YAML::Value << t.serialization;
    y << YAML::Key << "offered_qos_profiles" << YAML::Value << "" << YAML::EndMap;
    y << YAML::Key << "message_count" << YAML::Value << t.messages << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "compression_format" << YAML::Value << "" << YAML::Key << "compression_mode"
    << YAML::Value << "";
  y << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq << file << YAML::EndSeq;
  y << YAML::Key << "files" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "path" << YAML::Value << file;
  y << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch"
    << YAML::Value << start << YAML::EndMap;
  y << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds" << YAML::Value
    << duration << YAML::EndMap;
  y << YAML::Key << "message_count" << YAML::Value << m.messages << YAML::EndMap << YAML::EndSeq;
  y << YAML::EndMap << YAML::EndMap;
  {
    std::ofstream out(fs::path(m.part) / "metadata.yaml");
    out << y.c_str() << '\n';
    if (!out) throw std::runtime_error(m.part + "/metadata.yaml: write failed");
  }
  fs::rename(m.part, m.dir);
}

}  // namespace dloam::io
