#include "server/backup.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <vector>

#include <sqlite3.h>

#include "server/sql.hpp"

extern char** environ;

namespace cathbox::server {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSqliteMagic("SQLite format 3\0", 16);  // the first 16 bytes of every SQLite file
constexpr char kPgDumpMagic[] = "PGDMP";            // pg_dump's custom format

bool is_sqlite_url(const std::string& url) { return url.rfind("sqlite:", 0) == 0; }

std::string sqlite_path(const std::string& url) {
  std::string path = url.substr(7);
  if (path.rfind("//", 0) == 0) path = path.substr(2);
  return path;
}

std::string file_head(const std::string& file, std::size_t n) {
  std::ifstream in(file, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

// Runs `argv` (found on PATH), standard error to `log`; its exit status, or -1 if it did not start.
int run_tool(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The first line of a tool's standard error (its own one-line reason), or "exit N".
std::string tool_reason(const std::string& log, int rc) {
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);
  std::error_code ignored;
  fs::remove(log, ignored);
  return line.empty() ? "exit " + std::to_string(rc) : line;
}

// The tables a database holds in its schema (SQLite: the file's; PostgreSQL: `public`).
long long table_count(const std::string& url, Error& error) {
  DatabaseOpen opened = open_database(url);
  if (!opened.db) {
    error = make_error(503, opened.error);
    return -1;
  }
  long long n = 0;
  try {
    opened.db->transact(TxMode::kRead, [&](SqlSession& s) {
      const std::string sql = s.dialect() == SqlDialect::kSqlite
                                  ? "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table'"
                                  : "SELECT COUNT(*) FROM information_schema.tables WHERE table_schema = 'public'";
      n = s.query_one(sql)->integer(0);
    });
  } catch (const StoreError& e) {
    error = make_error(503, e.what());
    return -1;
  }
  return n;
}

// Copies database `from` into `to` with SQLite's backup API, all pages in one step.
Status sqlite_copy(sqlite3* from, sqlite3* to, const std::string& what) {
  sqlite3_backup* b = sqlite3_backup_init(to, "main", from, "main");
  if (b == nullptr) return make_error(503, what + ": " + sqlite3_errmsg(to));
  const int step = sqlite3_backup_step(b, -1);
  const int finish = sqlite3_backup_finish(b);
  if (step != SQLITE_DONE || finish != SQLITE_OK) {
    return make_error(503, what + ": " + sqlite3_errstr(step != SQLITE_DONE ? step : finish));
  }
  return Ok{};
}

struct SqliteHandle {
  sqlite3* db = nullptr;
  ~SqliteHandle() { sqlite3_close_v2(db); }
};

Status open_sqlite(const std::string& path, int flags, SqliteHandle& h, const std::string& what) {
  if (sqlite3_open_v2(path.c_str(), &h.db, flags, nullptr) != SQLITE_OK) {
    return make_error(503, what + ": " + (h.db != nullptr ? sqlite3_errmsg(h.db) : "out of memory"));
  }
  sqlite3_busy_timeout(h.db, 10000);
  return Ok{};
}

Status finish_file(const std::string& partial, const std::string& file) {
  std::error_code ec;
  fs::rename(partial, file, ec);
  if (ec) return make_error(400, file + ": cannot write: " + ec.message());
  return Ok{};
}

}  // namespace

Status backup_database(const std::string& db_url, const std::string& file) {
  const std::string partial = file + ".partial";
  std::error_code ignored;
  fs::remove(partial, ignored);
  if (std::ofstream probe(partial, std::ios::binary); !probe) return make_error(400, file + ": cannot write: " + std::strerror(errno));
  if (is_sqlite_url(db_url)) {
    const std::string path = sqlite_path(db_url);
    if (!fs::exists(path)) return make_error(400, "--db " + db_url + ": no such database file");
    SqliteHandle from, to;
    Status s = open_sqlite(path, SQLITE_OPEN_READONLY, from, "--db " + db_url);
    if (s) s = open_sqlite(partial, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, to, file);
    if (s) s = sqlite_copy(from.db, to.db, "backup of " + path);
    if (!s) {
      fs::remove(partial, ignored);
      return s;
    }
    return finish_file(partial, file);
  }
  const std::string log = partial + ".log";
  const int rc = run_tool({"pg_dump", "--format=custom", "--no-owner", "--file=" + partial, "--dbname=" + db_url}, log);
  if (rc != 0) {
    fs::remove(partial, ignored);
    if (rc < 0) return make_error(503, "backup: pg_dump cannot be run (Debian package postgresql-client)");
    return make_error(503, "backup: pg_dump: " + tool_reason(log, rc));
  }
  fs::remove(log, ignored);
  return finish_file(partial, file);
}

Status restore_database(const std::string& db_url, const std::string& file) {
  if (!fs::is_regular_file(file)) return make_error(400, file + ": no such backup file");
  const std::string head = file_head(file, 16);
  const bool sqlite_file = head == kSqliteMagic;
  const bool pg_dump_file = head.rfind(kPgDumpMagic, 0) == 0;
  if (!sqlite_file && !pg_dump_file) {
    return make_error(400, file + ": not a cathbox backup (neither a SQLite database nor a pg_dump custom-format file)");
  }
  if (is_sqlite_url(db_url) != sqlite_file) {
    return make_error(400, file + ": a " + (sqlite_file ? std::string("SQLite") : std::string("PostgreSQL")) +
                               " backup: restore it with a " + (sqlite_file ? "sqlite:PATH" : "postgresql://...") + " --db");
  }
  if (sqlite_file) {
    const std::string path = sqlite_path(db_url);
    if (fs::exists(path) && fs::file_size(path) > 0) {
      return make_error(400, "--db " + db_url + ": the file exists; a restore goes into a new database file");
    }
    SqliteHandle from, check;
    Status s = open_sqlite(file, SQLITE_OPEN_READONLY, from, file);
    if (s && sqlite3_exec(from.db, "SELECT version FROM schema_migrations LIMIT 1", nullptr, nullptr, nullptr) != SQLITE_OK) {
      return make_error(400, file + ": a SQLite database, but not a cathbox one (no schema_migrations table)");
    }
    const std::string partial = path + ".partial";
    std::error_code ignored;
    fs::remove(partial, ignored);
    SqliteHandle to;
    if (s) s = open_sqlite(partial, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, to, "--db " + db_url);
    if (s) s = sqlite_copy(from.db, to.db, "restore of " + file);
    if (!s) {
      fs::remove(partial, ignored);
      return s;
    }
    return finish_file(partial, path);
  }
  Error error;
  const long long tables = table_count(db_url, error);
  if (tables < 0) return error;
  if (tables > 0) {
    return make_error(400, "--db: the database is not empty (" + std::to_string(tables) +
                               " tables); a restore goes into an empty database");
  }
  const std::string log = file + ".restore.log";
  const int rc = run_tool({"pg_restore", "--single-transaction", "--exit-on-error", "--no-owner", "--dbname=" + db_url, file}, log);
  if (rc < 0) return make_error(503, "restore: pg_restore cannot be run (Debian package postgresql-client)");
  if (rc != 0) return make_error(503, "restore: pg_restore: " + tool_reason(log, rc));
  std::error_code ignored;
  fs::remove(log, ignored);
  return Ok{};
}

}  // namespace cathbox::server
