#include "pg_database.hpp"
#include "server/sql.hpp"
#include "sqlite_database.hpp"

namespace cathbox::server {

DatabaseOpen open_database(std::string_view url, const DatabaseOptions& options) {
  const std::string u(url);
  if (u.rfind("sqlite:", 0) == 0) {
    std::string path = u.substr(7);
    // Accept sqlite:///abs/path and sqlite://rel as well as sqlite:PATH.
    if (path.rfind("//", 0) == 0) path = path.substr(2);
    return open_sqlite_database(path, options);
  }
  if (u.rfind("postgresql://", 0) == 0 || u.rfind("postgres://", 0) == 0) return open_pg_database(u, options);
  DatabaseOpen out;
  const std::size_t colon = u.find(':');
  out.error = "--db: unknown database '" + (colon == std::string::npos ? u : u.substr(0, colon + 1)) +
              "' (use sqlite:PATH or postgresql://...)";
  return out;
}

}  // namespace cathbox::server
