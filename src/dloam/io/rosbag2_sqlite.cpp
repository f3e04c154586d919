// One rosbag2 SQLite storage file (.db3) through libsqlite3: tables topics(id, name, type,
// serialization_format, ...) and messages(id, topic_id, timestamp, data).
#include <sqlite3.h>

#include <cstring>
#include <map>
#include <memory>

#include "dloam/core/types.hpp"
#include "dloam/io/bag.hpp"

namespace dloam::io::bag_detail {

namespace {
[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

struct Statement {
  sqlite3_stmt* stmt = nullptr;
  Statement() = default;
  Statement(Statement&& o) noexcept : stmt(o.stmt) { o.stmt = nullptr; }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  Statement& operator=(Statement&&) = delete;
  ~Statement() { sqlite3_finalize(stmt); }
};

class SqliteFile : public BagFile {
 public:
  /// An SQLite image held in memory (fuzzing, tests); `name` is used in errors.
  SqliteFile(std::string name, const std::vector<std::uint8_t>& bytes) : path_(std::move(name)) {
    sqlite3* db = nullptr;
    const int opened = sqlite3_open_v2(":memory:", &db, SQLITE_OPEN_READWRITE, nullptr);
    db_.reset(db);
    if (opened != SQLITE_OK) fail(path_, "cannot be opened (sqlite: out of memory)");
    auto* copy = static_cast<unsigned char*>(sqlite3_malloc64(bytes.size()));
    if (!copy && !bytes.empty()) fail(path_, "cannot be opened (sqlite: out of memory)");
    if (!bytes.empty()) std::memcpy(copy, bytes.data(), bytes.size());
    const int rc = sqlite3_deserialize(db_.get(), "main", copy, static_cast<sqlite3_int64>(bytes.size()),
                                       static_cast<sqlite3_int64>(bytes.size()),
                                       SQLITE_DESERIALIZE_FREEONCLOSE | SQLITE_DESERIALIZE_READONLY);
    if (rc != SQLITE_OK)
      fail(path_, std::string("cannot be opened (sqlite: ") + sqlite3_errmsg(db_.get()) + ")");
    check_tables();
  }

  explicit SqliteFile(std::string path) : path_(std::move(path)) {
    open(false);
    try {
      check_tables();
    } catch (const InputError&) {
      // A bag in a read-only folder whose journal SQLite cannot lock: read it as immutable.
      if (sqlite3_errcode(db_.get()) != SQLITE_CANTOPEN && sqlite3_errcode(db_.get()) != SQLITE_BUSY &&
          sqlite3_errcode(db_.get()) != SQLITE_READONLY)
        throw;
      db_.reset();
      open(true);
      check_tables();
    }
  }

  [[nodiscard]] const std::string& path() const override { return path_; }
  [[nodiscard]] std::string format() const override { return "rosbag2 SQLite"; }

  std::vector<BagTopic> topics() override {
    std::vector<BagTopic> out;
    Statement s = prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    std::map<std::int64_t, std::size_t> by_id;
    while (step(s, "reading the topics table")) {
      BagTopic t;
      t.name = text(s.stmt, 1);
      t.type = text(s.stmt, 2);
      t.encoding = text(s.stmt, 3);
      by_id[sqlite3_column_int64(s.stmt, 0)] = out.size();
      ids_[t.name] = sqlite3_column_int64(s.stmt, 0);
      out.push_back(t);
    }
    Statement c = prepare("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
    while (step(c, "counting the messages")) {
      const auto it = by_id.find(sqlite3_column_int64(c.stmt, 0));
      if (it != by_id.end())
        out[it->second].messages = static_cast<std::size_t>(sqlite3_column_int64(c.stmt, 1));
    }
    return out;
  }

  std::vector<MessageRef> index(const std::string& topic) override {
    if (ids_.empty()) (void)topics();
    const auto it = ids_.find(topic);
    if (it == ids_.end()) return {};
    Statement s = prepare("SELECT id, timestamp FROM messages WHERE topic_id = ? ORDER BY timestamp, id");
    sqlite3_bind_int64(s.stmt, 1, it->second);
    std::vector<MessageRef> out;
    while (step(s, "listing the messages of topic " + topic))
      out.push_back(
          {sqlite3_column_int64(s.stmt, 1), static_cast<std::uint64_t>(sqlite3_column_int64(s.stmt, 0))});
    return out;
  }

  std::vector<std::uint8_t> read(const MessageRef& ref, const std::string& where) override {
    if (!read_) read_ = std::make_unique<Statement>(prepare("SELECT data FROM messages WHERE id = ?"));
    sqlite3_reset(read_->stmt);
    sqlite3_bind_int64(read_->stmt, 1, static_cast<sqlite3_int64>(ref.locator));
    const int rc = sqlite3_step(read_->stmt);
    if (rc != SQLITE_ROW)
      fail(where, rc == SQLITE_DONE
                      ? std::string("message row vanished from the file")
                      : std::string("cannot be read (sqlite: ") + sqlite3_errmsg(db_.get()) + ")");
    const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(read_->stmt, 0));
    const auto n = static_cast<std::size_t>(sqlite3_column_bytes(read_->stmt, 0));
    std::vector<std::uint8_t> out(blob, blob + n);
    sqlite3_reset(read_->stmt);
    return out;
  }

 private:
  void open(bool immutable) {
    const std::string name = immutable ? "file:" + path_ + "?immutable=1" : path_;
    const int flags = SQLITE_OPEN_READONLY | (immutable ? SQLITE_OPEN_URI : 0);
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(name.c_str(), &db, flags, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK)
      fail(path_,
           "cannot be opened (sqlite: " + std::string(db ? sqlite3_errmsg(db) : "out of memory") + ")");
  }

  void check_tables() {
    Statement s = prepare("SELECT name FROM sqlite_master WHERE type = 'table'");
    bool topics = false, messages = false;
    while (step(s, "reading the table list")) {
      const std::string t = text(s.stmt, 0);
      topics |= t == "topics";
      messages |= t == "messages";
    }
    if (!topics || !messages)
      fail(path_, "is an SQLite file but not a rosbag2 bag (no topics / messages tables)");
  }

  Statement prepare(const char* sql) {
    Statement s;
    if (sqlite3_prepare_v2(db_.get(), sql, -1, &s.stmt, nullptr) != SQLITE_OK)
      fail(path_,
           std::string("not a readable rosbag2 SQLite file (sqlite: ") + sqlite3_errmsg(db_.get()) + ")");
    return s;
  }

  bool step(Statement& s, const std::string& doing) {
    const int rc = sqlite3_step(s.stmt);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(path_,
         "not a readable rosbag2 SQLite file (sqlite, " + doing + ": " + sqlite3_errmsg(db_.get()) + ")");
  }

  static std::string text(sqlite3_stmt* s, int col) {
    const auto* p = sqlite3_column_text(s, col);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  }

  struct CloseDb {
    void operator()(sqlite3* db) const { sqlite3_close(db); }
  };
  std::string path_;
  std::unique_ptr<sqlite3, CloseDb> db_;  // declared before the statements: closed after them
  std::map<std::string, std::int64_t> ids_;
  std::unique_ptr<Statement> read_;
};
}  // namespace

std::unique_ptr<BagFile> open_sqlite_file(const std::string& path) {
  return std::make_unique<SqliteFile>(path);
}

std::unique_ptr<BagFile> open_sqlite_memory(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  return std::make_unique<SqliteFile>(name, bytes);
}

}  // namespace dloam::io::bag_detail
