#include "sqlite_database.hpp"

#include "connection_pool.hpp"

#include <sqlite3.h>

#include <filesystem>
#include <unordered_map>
#include <vector>

namespace cathbox::server {

namespace {

class Connection {
 public:
  explicit Connection(sqlite3* db) : db_(db) {}
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection() {
    for (auto& [sql, stmt] : statements_) sqlite3_finalize(stmt);
    sqlite3_close_v2(db_);
  }
  [[nodiscard]] sqlite3* handle() const { return db_; }

  // A prepared statement for this text, reset and unbound, cached for the connection's life.
  sqlite3_stmt* statement(std::string_view sql) {
    auto it = statements_.find(std::string(sql));
    if (it != statements_.end()) {
      sqlite3_reset(it->second);
      sqlite3_clear_bindings(it->second);
      return it->second;
    }
    sqlite3_stmt* stmt = nullptr;
    const int rc = sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT, &stmt, nullptr);
    if (rc != SQLITE_OK) fail(rc, "prepare");
    statements_.emplace(std::string(sql), stmt);
    return stmt;
  }

  [[noreturn]] void fail(int rc, const char* what) const {
    const int primary = rc & 0xff;
    const bool retry = primary == SQLITE_BUSY || primary == SQLITE_LOCKED || primary == SQLITE_FULL ||
                       primary == SQLITE_IOERR || primary == SQLITE_CANTOPEN;
    throw StoreError(retry ? StoreError::Kind::kUnavailable : StoreError::Kind::kInternal,
                     std::string("sqlite ") + what + ": " + sqlite3_errmsg(db_));
  }

 private:
  sqlite3* db_;
  std::unordered_map<std::string, sqlite3_stmt*> statements_;
};

class SqliteSession final : public SqlSession {
 public:
  explicit SqliteSession(Connection& c) : c_(c) {}
  [[nodiscard]] SqlDialect dialect() const override { return SqlDialect::kSqlite; }

  std::vector<SqlRow> query(std::string_view sql, const std::vector<SqlValue>& params) override {
    sqlite3_stmt* stmt = c_.statement(sql);
    if (sqlite3_bind_parameter_count(stmt) != static_cast<int>(params.size())) {
      throw StoreError(StoreError::Kind::kInternal, "statement takes " + std::to_string(sqlite3_bind_parameter_count(stmt)) +
                                                        " parameters, given " + std::to_string(params.size()));
    }
    for (std::size_t i = 0; i < params.size(); ++i) {
      const std::string name = "$" + std::to_string(i + 1);
      const int index = sqlite3_bind_parameter_index(stmt, name.c_str());
      if (index == 0) throw StoreError(StoreError::Kind::kInternal, "statement does not use parameter " + name);
      int rc = SQLITE_OK;
      const SqlValue& v = params[i];
      if (std::holds_alternative<std::nullptr_t>(v)) {
        rc = sqlite3_bind_null(stmt, index);
      } else if (const auto* n = std::get_if<std::int64_t>(&v)) {
        rc = sqlite3_bind_int64(stmt, index, *n);
      } else if (const auto* d = std::get_if<double>(&v)) {
        rc = sqlite3_bind_double(stmt, index, *d);
      } else if (const auto* s = std::get_if<std::string>(&v)) {
        rc = sqlite3_bind_text64(stmt, index, s->data(), s->size(), SQLITE_TRANSIENT, SQLITE_UTF8);
      } else {
        const Blob& b = std::get<Blob>(v);
        rc = sqlite3_bind_blob64(stmt, index, b.bytes.data(), b.bytes.size(), SQLITE_TRANSIENT);
      }
      if (rc != SQLITE_OK) c_.fail(rc, "bind");
    }
    std::vector<SqlRow> rows;
    for (;;) {
      const int rc = sqlite3_step(stmt);
      if (rc == SQLITE_DONE) break;
      if (rc != SQLITE_ROW) {
        sqlite3_reset(stmt);
        c_.fail(rc, "step");
      }
      const int n = sqlite3_column_count(stmt);
      std::vector<SqlValue> fields;
      fields.reserve(static_cast<std::size_t>(n));
      for (int col = 0; col < n; ++col) {
        switch (sqlite3_column_type(stmt, col)) {
          case SQLITE_INTEGER: fields.emplace_back(static_cast<std::int64_t>(sqlite3_column_int64(stmt, col))); break;
          case SQLITE_FLOAT: fields.emplace_back(sqlite3_column_double(stmt, col)); break;
          case SQLITE_TEXT: {
            const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt, col));
            fields.emplace_back(std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt, col))));
            break;
          }
          case SQLITE_BLOB: {
            const auto* p = static_cast<const char*>(sqlite3_column_blob(stmt, col));
            const auto len = static_cast<std::size_t>(sqlite3_column_bytes(stmt, col));
            fields.emplace_back(Blob{p == nullptr ? std::string() : std::string(p, len)});
            break;
          }
          default: fields.emplace_back(nullptr); break;
        }
      }
      rows.emplace_back(std::move(fields));
    }
    sqlite3_reset(stmt);
    return rows;
  }

  void run_script(std::string_view sql) override {
    char* message = nullptr;
    const int rc = sqlite3_exec(c_.handle(), std::string(sql).c_str(), nullptr, nullptr, &message);
    if (rc != SQLITE_OK) {
      const std::string text = message != nullptr ? message : "unknown error";
      sqlite3_free(message);
      throw StoreError(StoreError::Kind::kInternal, "sqlite script: " + text);
    }
  }

 private:
  Connection& c_;
};

class SqliteDatabase final : public Database {
 public:
  SqliteDatabase(std::string path, const DatabaseOptions& options)
      : path_(std::move(path)), options_(options), pool_(path_ == ":memory:" ? 1 : options.pool_size, [this] { return connect(); }) {}

  [[nodiscard]] SqlDialect dialect() const override { return SqlDialect::kSqlite; }
  [[nodiscard]] std::string describe() const override { return "sqlite:" + path_; }
  [[nodiscard]] PoolStats pool_stats() const override { return pool_.stats(); }

  // Opens the first connection (so a bad path fails at start-up).
  std::string open_first() {
    try {
      pool_.open_first();
    } catch (const StoreError& e) {
      return e.what();
    }
    return {};
  }

  void scrub() override {
    if (path_ == ":memory:") return;
    std::unique_ptr<Connection> c = pool_.acquire();
    sqlite3_exec(c->handle(), "PRAGMA wal_checkpoint(TRUNCATE)", nullptr, nullptr, nullptr);
    pool_.release(std::move(c));
  }

  void transact(TxMode mode, const std::function<void(SqlSession&)>& work) override {
    std::unique_ptr<Connection> c = pool_.acquire();
    struct Release {
      ConnectionPool<Connection>& pool;
      std::unique_ptr<Connection>& c;
      ~Release() { pool.release(std::move(c)); }
    } release{pool_, c};
    SqliteSession session(*c);
    session.run_script(mode == TxMode::kWrite ? "BEGIN IMMEDIATE" : "BEGIN");
    try {
      work(session);
      session.run_script("COMMIT");
    } catch (...) {
      sqlite3_exec(c->handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }

 private:
  std::unique_ptr<Connection> connect() {
    sqlite3* db = nullptr;
    const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX;
    const int rc = sqlite3_open_v2(path_.c_str(), &db, flags, nullptr);
    if (rc != SQLITE_OK) {
      const std::string message = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
      sqlite3_close_v2(db);
      throw StoreError(StoreError::Kind::kUnavailable, "sqlite:" + path_ + ": " + message);
    }
    auto c = std::make_unique<Connection>(db);
    sqlite3_busy_timeout(db, options_.busy_timeout_ms);
    sqlite3_extended_result_codes(db, 1);
    SqliteSession s(*c);
    try {
      // journal_mode answers a row; the others are silent.
      (void)s.query(path_ == ":memory:" ? "PRAGMA journal_mode=MEMORY" : "PRAGMA journal_mode=WAL", {});
      // secure_delete: deleted rows (a deleted trainee's records) are overwritten, not left in free
      // pages (Debian builds SQLite with it on by default; said here so no other build differs).
      s.run_script("PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON; PRAGMA secure_delete=ON;");
    } catch (const StoreError& e) {
      throw StoreError(StoreError::Kind::kUnavailable, "sqlite:" + path_ + ": " + e.what());
    }
    return c;
  }

  std::string path_;
  DatabaseOptions options_;
  ConnectionPool<Connection> pool_;
};

}  // namespace

DatabaseOpen open_sqlite_database(const std::string& path, const DatabaseOptions& options) {
  DatabaseOpen out;
  if (path.empty()) {
    out.error = "--db sqlite: needs a path (sqlite:/path/to/file.db or sqlite::memory:)";
    return out;
  }
  if (path != ":memory:") {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (ec) {
      out.error = "sqlite:" + path + ": cannot create folder " + parent.string() + ": " + ec.message();
      return out;
    }
  }
  auto db = std::make_unique<SqliteDatabase>(path, options);
  out.error = db->open_first();
  if (out.error.empty()) out.db = std::move(db);
  return out;
}

}  // namespace cathbox::server
