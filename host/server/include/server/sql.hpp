#pragma once
// The one interface both databases implement: parameterised statements in transactions.
//
// Statements are written once, with PostgreSQL-style placeholders ($1, $2, ...), which SQLite
// also accepts as named parameters, so the Store's queries are the same text on both databases
// (only the schema's DDL differs, see migrations.cpp). Values are only ever bound as parameters,
// never spliced into the text.
//
// Failures of the database itself (gone, locked for too long, disk full) throw StoreError; the
// request boundary answers them with 503 so clients retry. Everything else is a result value.
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace cathbox::server {

// Bytes bound or read as a BLOB / BYTEA.
struct Blob {
  std::string bytes;
};

using SqlValue = std::variant<std::nullptr_t, std::int64_t, double, std::string, Blob>;

class StoreError : public std::runtime_error {
 public:
  enum class Kind {
    kUnavailable,  // connection lost or refused, database busy: the operation may be retried
    kInternal      // a statement failed (a bug, or a database not made by these migrations)
  };
  StoreError(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  [[nodiscard]] Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

// One result row; accessors convert between the two databases' representations (PostgreSQL
// answers integers as int8, SQLite may store 2.0 as an integer).
class SqlRow {
 public:
  explicit SqlRow(std::vector<SqlValue> fields) : fields_(std::move(fields)) {}
  [[nodiscard]] std::size_t size() const { return fields_.size(); }
  [[nodiscard]] bool is_null(std::size_t i) const;
  [[nodiscard]] std::int64_t integer(std::size_t i) const;  // null reads as 0
  [[nodiscard]] double real(std::size_t i) const;          // null reads as 0
  [[nodiscard]] std::string text(std::size_t i) const;     // text or blob bytes; null reads as ""
  [[nodiscard]] std::optional<std::int64_t> optional_integer(std::size_t i) const;

 private:
  std::vector<SqlValue> fields_;
};

enum class SqlDialect { kSqlite, kPostgresql };

// A connection inside one transaction.
class SqlSession {
 public:
  virtual ~SqlSession() = default;
  [[nodiscard]] virtual SqlDialect dialect() const = 0;
  // Runs one statement with its parameters, returns its rows (RETURNING included).
  virtual std::vector<SqlRow> query(std::string_view sql, const std::vector<SqlValue>& params) = 0;
  // Runs a script of statements without parameters (schema migrations only).
  virtual void run_script(std::string_view sql) = 0;

  std::vector<SqlRow> query(std::string_view sql, std::initializer_list<SqlValue> params = {}) {
    return query(sql, std::vector<SqlValue>(params));
  }
  std::optional<SqlRow> query_one(std::string_view sql, std::initializer_list<SqlValue> params = {}) {
    return query_one(sql, std::vector<SqlValue>(params));
  }
  std::optional<SqlRow> query_one(std::string_view sql, const std::vector<SqlValue>& params);
};

enum class TxMode { kRead, kWrite };

// A connection pool's state now (for /metrics).
struct PoolStats {
  int open = 0;     // connections open, idle or in use
  int idle = 0;
  int max = 0;
  int waiting = 0;  // callers waiting for a connection
};

class Database {
 public:
  virtual ~Database() = default;
  [[nodiscard]] virtual SqlDialect dialect() const = 0;
  // "sqlite:/path/file.db" or "postgresql://host/db" with any password removed.
  [[nodiscard]] virtual std::string describe() const = 0;
  // Runs `work` in one transaction on a pooled connection and commits when it returns. A
  // connection that broke before the commit is replaced and `work` runs again (so it must only
  // touch the database); a database that stays unreachable for `Options::retry_ms` throws
  // StoreError(kUnavailable). An exception from `work` rolls back and propagates.
  virtual void transact(TxMode mode, const std::function<void(SqlSession&)>& work) = 0;
  [[nodiscard]] virtual PoolStats pool_stats() const = 0;
  // After personal data was deleted: removes the copies of the deleted rows' bytes the database
  // still keeps in its files, as far as it can without stopping. SQLite zeroes deleted content as
  // it goes (secure_delete) and here checkpoints and truncates its write-ahead log (best effort:
  // a read open at that moment leaves the log to the next checkpoint). PostgreSQL: nothing (its
  // dead rows stay in the table files until VACUUM reuses the space: host/server/README.md).
  virtual void scrub() {}
};

struct DatabaseOptions {
  int pool_size = 8;           // connections kept open at most
  int retry_ms = 3000;         // how long a lost PostgreSQL is retried before 503
  int busy_timeout_ms = 10000; // SQLite: wait for the writer lock this long
};

struct DatabaseOpen {
  std::unique_ptr<Database> db;
  std::string error;  // one line when db is null ("--db: unknown scheme 'mysql:' ...")
};

// "sqlite:PATH" (PATH may be ":memory:") or "postgresql://..." / "postgres://..." (any libpq
// connection URI). Connects once to fail early with a clear line.
[[nodiscard]] DatabaseOpen open_database(std::string_view url, const DatabaseOptions& options = {});

// Text of a double that reads back to the same value (shortest round trip).
[[nodiscard]] std::string sql_double_text(double v);

}  // namespace cathbox::server
