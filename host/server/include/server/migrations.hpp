#pragma once
// Versioned schema migrations, applied in order at start-up inside one transaction (under an
// advisory lock on PostgreSQL, BEGIN IMMEDIATE on SQLite, so two servers starting at once apply
// each migration once). Every applied version is a row in schema_migrations. A database whose
// schema is newer than this program is refused rather than touched.
#include <string>
#include <vector>

#include "server/result.hpp"
#include "server/sql.hpp"

namespace cathbox::server {

struct Migration {
  int version;
  const char* name;
  // One schema text for both databases; {id}, {blob}, {real} and {unlogged} are replaced per
  // dialect (see migrations.cpp).
  const char* sql;
};

// The project's migrations, oldest first (versions 1, 2, 3, ...).
[[nodiscard]] const std::vector<Migration>& schema_migrations();
[[nodiscard]] int latest_schema_version();

struct MigrationReport {
  int from_version = 0;
  int to_version = 0;
};

// Brings the schema up to `target` (default: the latest). Refuses (409) a database already past
// what this program knows.
[[nodiscard]] Result<MigrationReport> migrate(Database& db, int target = -1);

// The version recorded in the database (0 when none).
[[nodiscard]] int schema_version(Database& db);

}  // namespace cathbox::server
