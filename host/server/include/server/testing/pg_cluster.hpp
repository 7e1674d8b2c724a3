#pragma once
// A real, throwaway PostgreSQL for tests and benchmarks: Debian's initdb and pg_ctl into a new
// temporary folder, listening only on a Unix socket in that folder (no TCP port), torn down by
// the destructor. PostgreSQL refuses to run as root, so when the caller is root the cluster
// runs as the `postgres` system user the package creates, owning the folder.
//
// A reaper process (its own session, so a test killed by a timeout does not take it along)
// watches a pipe from the owner; when the owner goes away by any route it stops the cluster
// and removes the folder. Nothing is left running after a test.
#include <memory>
#include <string>
#include <vector>
#include <sys/types.h>

#include "server/result.hpp"

namespace cathbox::server::testing {

struct PgClusterOptions {
  bool fsync = false;  // off for tests (a process crash loses nothing; a machine crash is not tested)
  int max_connections = 100;
};

class PgCluster {
 public:
  // initdb + pg_ctl start -w, and a database named `cathbox`.
  [[nodiscard]] static Result<std::unique_ptr<PgCluster>> start(const PgClusterOptions& options = {});
  ~PgCluster();
  PgCluster(const PgCluster&) = delete;
  PgCluster& operator=(const PgCluster&) = delete;

  // postgresql:///DATABASE?host=FOLDER&user=cathbox
  [[nodiscard]] std::string url(const std::string& database = "cathbox") const;
  [[nodiscard]] Status create_database(const std::string& name);
  // pg_ctl stop -m MODE ("fast" or "immediate") and start -w again, same data.
  [[nodiscard]] Status stop(const std::string& mode = "fast");
  [[nodiscard]] Status start_again();
  [[nodiscard]] const std::string& folder() const { return folder_; }
  [[nodiscard]] std::string log_tail(std::size_t bytes = 2000) const;

  // Where Debian puts the server programs (/usr/lib/postgresql/<major>/bin), or "".
  [[nodiscard]] static std::string bin_dir();

 private:
  PgCluster() = default;
  [[nodiscard]] int pg(const std::vector<std::string>& argv) const;
  std::string folder_;
  std::string bin_;
  PgClusterOptions options_;
  bool as_postgres_ = false;
  uid_t uid_ = 0;
  gid_t gid_ = 0;
  pid_t reaper_ = -1;
  int reaper_pipe_ = -1;
  bool running_ = false;
};

}  // namespace cathbox::server::testing
