#pragma once
// SQLite behind the Database interface: a small pool of connections to one file in WAL mode
// (readers never wait for the writer), writes in BEGIN IMMEDIATE transactions, synchronous=FULL
// so a commit that returned survives a crash of the process or the machine.
#include <memory>
#include <string>

#include "server/sql.hpp"

namespace cathbox::server {

// `path` is a file path or ":memory:" (one private in-memory database, pool of one).
[[nodiscard]] DatabaseOpen open_sqlite_database(const std::string& path, const DatabaseOptions& options);

}  // namespace cathbox::server
