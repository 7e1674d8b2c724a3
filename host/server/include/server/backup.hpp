#pragma once
// Backup and restore of the centre's database (`cathbox-server admin backup FILE`, `admin
// restore FILE`).
//
// SQLite: SQLite's online backup API copies the whole file in one step under one read snapshot,
// so a backup taken while the server serves is consistent (WAL: the server's writers do not wait
// for it). The backup is itself a SQLite database file.
// PostgreSQL: `pg_dump --format=custom` (one consistent snapshot, serializable, no locks held
// against the server's writes); restored with `pg_restore --single-transaction`.
//
// Either way the file is written as FILE.partial and renamed when complete, so a failed backup
// never leaves a FILE that looks whole. A restore goes only into an empty database (a new SQLite
// path, or a PostgreSQL database with no tables) and checks the file's kind first; it either
// completes or leaves the target as it was.
#include <string>

#include "server/result.hpp"

namespace cathbox::server {

// 400: bad URL or file; 503: the database or pg_dump/pg_restore is unavailable.
[[nodiscard]] Status backup_database(const std::string& db_url, const std::string& file);
[[nodiscard]] Status restore_database(const std::string& db_url, const std::string& file);

}  // namespace cathbox::server
