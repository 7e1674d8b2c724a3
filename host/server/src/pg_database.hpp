#pragma once
// PostgreSQL behind the Database interface (libpqxx 6.4): a pool of connections; a connection
// that breaks (server restarted, network gone) is dropped and the transaction runs again on a
// new one until DatabaseOptions::retry_ms has passed, after which the caller gets
// StoreError(kUnavailable) and answers 503. A commit whose outcome is unknown (the connection
// broke while committing) is never retried here: the caller's retry is safe because every write
// the API acknowledges is idempotent or keyed.
#include <string>

#include "server/sql.hpp"

namespace cathbox::server {

[[nodiscard]] DatabaseOpen open_pg_database(const std::string& url, const DatabaseOptions& options);

// The URL without its password (for logs and --help output).
[[nodiscard]] std::string redact_pg_url(const std::string& url);

}  // namespace cathbox::server
