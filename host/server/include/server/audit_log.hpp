#pragma once
// The audit log: who did which administrative or instructor action, when, and from where
// (the client address, or "cli" for `cathbox-server admin`). Rows are only appended; an admin
// reads them through GET /api/v1/audit. The actor's name is kept as text, so an entry outlives
// the account that made it. Same statements on SQLite and PostgreSQL (migration 6).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/sql.hpp"

namespace cathbox::server {

struct AuditEntry {
  std::int64_t id = 0;
  std::int64_t at_us = 0;  // microseconds since the Unix epoch, the server's clock
  std::string actor;       // the account's name
  std::string action;      // e.g. "user.create", "assignment.delete"
  std::string target;      // what it acted on: a user's name, a case's name, an assignment's id
  std::string detail;      // the change, short ("role=instructor disabled=true")
  std::string remote;      // the client's address, or "cli"
};

struct AuditQuery {
  std::optional<std::int64_t> since_us;  // at or after
  std::optional<std::string> actor;
  int limit = 100;  // newest first
};

// Appends one entry (its own transaction); throws StoreError when the database fails.
void append_audit(Database& db, const AuditEntry& entry);
// Newest first.
[[nodiscard]] std::vector<AuditEntry> audit_entries(Database& db, const AuditQuery& query);

}  // namespace cathbox::server
