// rosbag2's sqlite3 storage: tables `topics` and `messages` (timestamp =
// receive time in ns, data = the CDR bytes), read row by row in time order.
#include "storage.hpp"

#include <lista/error.hpp>

#include <sqlite3.h>

#include <cstdio>
#include <map>
#include <sstream>

namespace lista::bag::ros2 {
namespace {

struct DbCloser {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtCloser {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbCloser>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtCloser>;

std::string column_text(sqlite3_stmt* s, int col) {
  const auto* t = sqlite3_column_text(s, col);
  return t ? reinterpret_cast<const char*>(t) : "";
}

class Sqlite {
 public:
  Sqlite(const std::string& file, int flags) : file_(file) {
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(file.c_str(), &db, flags, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK) fail("cannot open");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(file_ + ": " + what + ": " + (db_ ? sqlite3_errmsg(db_.get()) : "out of memory"));
  }
  Stmt prepare(const std::string& sql) const {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql.c_str(), -1, &s, nullptr) != SQLITE_OK) fail("not a rosbag2 SQLite file");
    return Stmt(s);
  }
  // Steps a statement; true for a row, false when done.
  bool step(sqlite3_stmt* s, const char* what) const {
    const int rc = sqlite3_step(s);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(what);
  }
  void exec(const std::string& sql) const {
    char* err = nullptr;
    if (sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : "unknown error";
      sqlite3_free(err);
      throw Error(file_ + ": " + msg);
    }
  }
  // Closes now, reporting what the destructor could not.
  void close() {
    if (sqlite3_close(db_.get()) != SQLITE_OK) fail("closing");
    db_.release();
  }

 private:
  std::string file_;
  Db db_;
};

class SqliteReader : public StorageReader {
 public:
  explicit SqliteReader(const std::string& file) : file_(file), db_(file, SQLITE_OPEN_READONLY) {
    std::map<int64_t, uint64_t> counts;
    Stmt c = db_.prepare("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
    while (db_.step(c.get(), "reading message counts")) counts[sqlite3_column_int64(c.get(), 0)] = sqlite3_column_int64(c.get(), 1);
    Stmt t = db_.prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    while (db_.step(t.get(), "reading topics")) {
      const int64_t id = sqlite3_column_int64(t.get(), 0);
      const std::string name = column_text(t.get(), 1);
      auto [it, fresh] = index_.emplace(name, topics_.size());
      if (fresh) topics_.push_back({name, column_text(t.get(), 2), column_text(t.get(), 3), 0});
      topics_[it->second].messages += counts[id];
      ids_[id] = it->second;
    }
  }

  const std::vector<StorageTopic>& topics() const override { return topics_; }
  const std::string& path() const override { return file_; }

  void read(const std::set<std::string>& wanted, const MessageSink& sink) override {
    std::ostringstream ids;
    for (const auto& [id, at] : ids_)
      if (wanted.count(topics_[at].name)) ids << (ids.tellp() > 0 ? "," : "") << id;
    if (ids.tellp() == 0) return;
    // The id breaks ties between equal timestamps: same order on every read.
    Stmt s = db_.prepare("SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids.str() +
                         ") ORDER BY timestamp, id");
    while (db_.step(s.get(), "reading messages")) {
      const int64_t id = sqlite3_column_int64(s.get(), 0);
      const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(s.get(), 2));
      const int size = sqlite3_column_bytes(s.get(), 2);
      sink(topics_[ids_.at(id)], sqlite3_column_int64(s.get(), 1), data, static_cast<size_t>(size));
    }
  }

 private:
  std::string file_;
  Sqlite db_;
  std::vector<StorageTopic> topics_;
  std::map<std::string, size_t> index_;
  std::map<int64_t, size_t> ids_;  // topics.id -> topics_
};

class SqliteWriter : public StorageWriter {
 public:
  explicit SqliteWriter(const std::string& file)
      : file_(file), part_(file + ".part"), db_((std::remove(part_.c_str()), part_), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) {
    db_.exec(
        "PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
        "BEGIN TRANSACTION;");
    topic_ = db_.prepare("INSERT INTO topics(id, name, type, serialization_format, offered_qos_profiles) VALUES(?, ?, ?, 'cdr', '')");
    message_ = db_.prepare("INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)");
  }
  ~SqliteWriter() override {
    if (!closed_) std::remove(part_.c_str());  // never closed: nothing looks complete
  }

  void write(const std::string& topic, const std::string& type, int64_t time_ns, const std::vector<uint8_t>& cdr) override {
    if (closed_) throw Error(file_ + ": written after close");
    auto it = ids_.find(topic);
    if (it == ids_.end()) {
      const int64_t id = static_cast<int64_t>(ids_.size()) + 1;
      sqlite3_reset(topic_.get());
      sqlite3_bind_int64(topic_.get(), 1, id);
      sqlite3_bind_text(topic_.get(), 2, topic.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(topic_.get(), 3, type.c_str(), -1, SQLITE_TRANSIENT);
      if (db_.step(topic_.get(), "writing a topic")) db_.fail("writing a topic");
      it = ids_.emplace(topic, id).first;
    }
    sqlite3_reset(message_.get());
    sqlite3_bind_int64(message_.get(), 1, it->second);
    sqlite3_bind_int64(message_.get(), 2, time_ns);
    sqlite3_bind_blob64(message_.get(), 3, cdr.data(), cdr.size(), SQLITE_STATIC);
    if (db_.step(message_.get(), "writing a message")) db_.fail("writing a message");
  }

  void close() override {
    if (closed_) return;
    topic_.reset();
    message_.reset();
    db_.exec("COMMIT;");
    db_.close();
    if (std::rename(part_.c_str(), file_.c_str()) != 0) throw Error(file_ + ": cannot rename " + part_ + " to it");
    closed_ = true;
  }

 private:
  std::string file_, part_;
  Sqlite db_;
  Stmt topic_, message_;
  std::map<std::string, int64_t> ids_;
  bool closed_ = false;
};

}  // namespace

std::unique_ptr<StorageReader> open_sqlite(const std::string& file) { return std::make_unique<SqliteReader>(file); }
std::unique_ptr<StorageWriter> create_sqlite(const std::string& file) { return std::make_unique<SqliteWriter>(file); }

}  // namespace lista::bag::ros2
