#pragma once
// The whole server assembled: the database (migrated), auth, case library, live hub and bus
// (PostgreSQL LISTEN/NOTIFY when the store is PostgreSQL), the API and the HTTP server. Used by
// cathbox-server's main, by tests (an in-process server on a free loopback port) and the bench.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "server/api.hpp"
#include "server/auth.hpp"
#include "server/case_library.hpp"
#include "server/clock.hpp"
#include "server/http_server.hpp"
#include "server/live_hub.hpp"
#include "server/live_service.hpp"
#include "server/pg_live_bus.hpp"
#include "server/record_checker.hpp"
#include "server/store.hpp"
#include "server/upload_limits.hpp"

namespace cathbox::server {

struct ServerConfig {
  std::string db_url;
  HttpServerOptions http;
  Argon2Params argon2;
  AuthOptions auth;
  LiveOptions live;
  DatabaseOptions database;
  std::string instance;             // empty: a random name
  Clock* clock = nullptr;           // null: the system clock
  std::unique_ptr<RecordChecker> checker;  // null: the session-replay checker when built
  std::string cache_dir;            // meshes and traces kept on disk too; empty: in memory only
  int maintenance_every_s = 60;     // purge expired tokens and old login failures, apply the retention; 0: no thread (tests call maintain_once)
  int record_retention_days = 0;    // records uploaded longer ago go (ServerCore::enforce_retention); 0: kept
};

// Everything but the sockets: database, auth, case library, live hub, bus and service, API.
class ServerCore {
 public:
  // Opens and migrates the database and starts the bus. Takes config.checker. The error's
  // status: 400 bad option, 409 schema newer than this program, 503 database unavailable.
  [[nodiscard]] static Result<std::unique_ptr<ServerCore>> open(ServerConfig& config);
  ~ServerCore();
  ServerCore(const ServerCore&) = delete;
  ServerCore& operator=(const ServerCore&) = delete;

  [[nodiscard]] const std::string& instance() const { return instance_; }
  [[nodiscard]] int schema_version() const { return schema_version_; }
  [[nodiscard]] Clock& clock() { return *clock_; }
  [[nodiscard]] Store& store() { return *store_; }
  [[nodiscard]] Auth& auth() { return *auth_; }
  [[nodiscard]] LiveHub& hub() { return hub_; }
  [[nodiscard]] LiveService& live() { return *live_; }
  [[nodiscard]] Api& api() { return *api_; }
  [[nodiscard]] PgLiveBus* pg_bus() { return pg_bus_.get(); }

  // The retention setting (ServerConfig::record_retention_days), at the clock's now: the records
  // of results uploaded more than that many days ago leave the store (Store::
  // drop_records_uploaded_before: the results and their metrics stay, marked record_gone_us),
  // their traces leave the cache, the database is scrubbed, and one audit row says how many
  // (actor "cathbox-server", action "records.retention", from "server"). Answers how many;
  // 0 and nothing done when the setting is 0. Run by ServerApp's maintenance; throws StoreError.
  int enforce_retention();

 private:
  ServerCore() = default;
  SystemClock system_clock_;
  Clock* clock_ = nullptr;
  std::string instance_;
  int schema_version_ = 0;
  int record_retention_days_ = 0;
  std::unique_ptr<Store> store_;
  std::unique_ptr<Auth> auth_;
  std::unique_ptr<CaseLibrary> cases_;
  LiveHub hub_;
  std::unique_ptr<LocalLiveBus> local_bus_;
  std::unique_ptr<PgLiveBus> pg_bus_;
  std::unique_ptr<LiveService> live_;
  std::unique_ptr<RecordChecker> checker_;
  ArtifactCache cache_;  // browser meshes, debrief traces
  std::unique_ptr<Api> api_;
};

// The core and the HTTP server, with a maintenance thread purging expired tokens and old login
// failures and applying the record retention, every ServerConfig::maintenance_every_s.
class ServerApp {
 public:
  [[nodiscard]] static Result<std::unique_ptr<ServerApp>> start(ServerConfig config);
  ~ServerApp();
  void stop();

  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] const std::string& instance() const { return core_->instance(); }
  [[nodiscard]] int schema_version() const { return core_->schema_version(); }
  [[nodiscard]] ServerCore& core() { return *core_; }
  [[nodiscard]] Store& store() { return core_->store(); }
  [[nodiscard]] Auth& auth() { return core_->auth(); }
  [[nodiscard]] HttpServer& http() { return *http_; }
  [[nodiscard]] PgLiveBus* pg_bus() { return core_->pg_bus(); }
  [[nodiscard]] std::string describe_db() const;
  // One pass of the maintenance thread, at the clock's now: expired tokens and old login failures
  // purged, the record retention applied (ServerCore::enforce_retention). A database away is
  // left to the next pass.
  void maintain_once();

 private:
  ServerApp() = default;
  void maintain();

  int maintenance_every_s_ = 60;
  std::int64_t failure_window_us_ = 0;
  std::unique_ptr<ServerCore> core_;
  std::unique_ptr<HttpServer> http_;
  std::uint16_t port_ = 0;
  std::thread maintenance_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
};

// The record checker over host/session (null when this build has no session module).
[[nodiscard]] std::unique_ptr<RecordChecker> make_session_checker(UploadLimits limits = {});

}  // namespace cathbox::server
