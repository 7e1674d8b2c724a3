#pragma once
// One account's data, for a subject-access request (`cathbox-server admin export-user NAME
// DIR`): into DIR (new, or an empty folder) it writes
//   user.json         the account row, without the password hash
//   assignments.json  the assignments made for them
//   results.json      their results, each with its metrics
//   records/ID.cbxrec each result's record, byte for byte as the server stores it
//   audit.json        the audit-log rows they made or that name them (the export's own included)
//   manifest.json     every other file's path, size in bytes and SHA-256
// The export is appended to the audit log (action "user.export") before the files are read, so
// audit.json holds it. Each part is read in its own transaction: a result uploaded during the
// export may or may not be in it, but every record listed is whole and matches its hash.
#include <cstdint>
#include <string>

#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct UserExport {
  int files = 0;  // counted in the manifest
  std::int64_t bytes = 0;
  int results = 0;
};

// 404: no such user (DIR untouched); 400: DIR exists and is not an empty folder, or cannot be
// written. `actor`: who asked (the audit row's actor; remote is "cli").
[[nodiscard]] Result<UserExport> export_user(Store& store, const std::string& name, const std::string& dir,
                                             const std::string& actor, std::int64_t now_us);

}  // namespace cathbox::server
